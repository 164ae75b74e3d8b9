// The browser app's import graph (frontend/src), checked by `npm run lint:deps` (part of
// `npm run lint`, so of `make lint` and `make test`). The layers are written down here once;
// a module imports only from its own layer or the layers below it, never in a cycle:
//
//   top      nav/* (the router table nav/routes.ts, the sidebar, the node layout), App.tsx,
//            main.tsx: they put the pages together, and nothing below imports them.
//   pages    pages/<name>/: one folder per page, private to itself. A page never imports
//            another page's modules: what two pages share moves down a layer.
//   shared   components/ (shared UI), session/, live/ (the WebSocket store), nav/paths.ts (the
//            app's URLs, a leaf that imports nothing, so any page can link to any other).
//   bottom   api/ (the generated client, the API's types and route calls), lib/ (pure helpers
//            and hooks), i18n/ (the languages and their catalogues), styles/ (the global CSS).
//
// Test code, that is *.test.ts(x), the pages' fixtures.ts and the helpers in test/, sits beside
// what it tests and keeps to the same layers; any test may also import test/ (render, fetch
// stub, the fixtures several folders share), and nothing else imports test code. test/ itself
// imports from the shared and bottom layers only.
//
// Paths are as depcruise prints them, from the repository root. dependency-cruiser stays on
// 17.x (package.json): 18 needs Node 22, and the app builds on Node 20.19 and later.

const BOTTOM = "^frontend/src/(api|i18n|lib|styles)/";
const SHARED = ["^frontend/src/(components|session|live)/", "^frontend/src/nav/paths[.]ts$"];
const PAGES = "^frontend/src/pages/";
const TOP = ["^frontend/src/nav/", "^frontend/src/App[.]tsx$", "^frontend/src/main[.]tsx$"];
const PATHS = "^frontend/src/nav/paths[.]ts$";
const TEST_SUPPORT = "^frontend/src/test/";
const TEST_CODE = ["[.]test[.]tsx?$", TEST_SUPPORT, "^frontend/src/pages/[^/]+/fixtures[.]ts$"];
const SRC = "^frontend/src/";

/** @type {import('dependency-cruiser').IConfiguration} */
module.exports = {
  forbidden: [
    {
      name: "no-circular",
      severity: "error",
      comment:
        "A cycle of imports (type-only imports count): the layers (.dependency-cruiser.cjs) " +
        "say which of the modules in it should not import the other.",
      from: {},
      to: { circular: true },
    },
    {
      name: "bottom-imports-bottom",
      severity: "error",
      comment:
        "api/, i18n/, lib/ and styles/ are the bottom layer: they import only each other, never " +
        "components/, session/, live/, nav/, the pages or the app.",
      from: { path: BOTTOM },
      to: { path: SRC, pathNot: [BOTTOM, TEST_SUPPORT] },
    },
    {
      name: "shared-below-pages",
      severity: "error",
      comment:
        "components/, session/, live/ and nav/paths.ts sit below the pages: they import only " +
        "each other, api/ and lib/. Move what they need from a page (a type, a call, a helper) " +
        "to api/ or lib/.",
      from: { path: SHARED },
      to: { path: SRC, pathNot: [BOTTOM, ...SHARED, TEST_SUPPORT] },
    },
    {
      name: "paths-is-a-leaf",
      severity: "error",
      comment:
        "nav/paths.ts (the app's URLs) imports nothing, so every layer can link to a page " +
        "without importing it.",
      from: { path: PATHS },
      to: { path: SRC },
    },
    {
      name: "pages-below-router",
      severity: "error",
      comment:
        "A page imports nothing from the top layer (nav/routes.ts, the sidebar, the layout, " +
        "App.tsx): a link to another page is nodeUrl() from nav/paths.ts; a shared helper " +
        "belongs in lib/ or components/.",
      from: { path: PAGES },
      to: { path: TOP, pathNot: PATHS },
    },
    {
      name: "page-private",
      severity: "error",
      comment:
        "A page folder is private: pages/X never imports pages/Y. Move what both use to api/ " +
        "(calls, types), components/ (UI), lib/ (pure helpers) or test/ (fixtures).",
      from: { path: "^frontend/src/pages/([^/]+)/" },
      to: { path: PAGES, pathNot: "^frontend/src/pages/$1/" },
    },
    {
      name: "test-support-below-pages",
      severity: "error",
      comment:
        "test/ serves the tests of every layer, so it imports only the shared and bottom " +
        "layers; a fixture two pages' tests share goes in test/fixtures/.",
      from: { path: TEST_SUPPORT },
      to: { path: SRC, pathNot: [BOTTOM, ...SHARED, TEST_SUPPORT] },
    },
    {
      name: "tests-only-from-tests",
      severity: "error",
      comment: "Only test code imports test code (*.test.ts(x), fixtures.ts, test/).",
      from: { pathNot: TEST_CODE },
      to: { path: TEST_CODE },
    },
    {
      name: "not-to-unresolvable",
      severity: "error",
      comment: "An import that resolves to no file: a moved module's importer was missed.",
      from: {},
      to: { couldNotResolve: true },
    },
  ],
  options: {
    // node_modules is left out of the graph: the rules are about the app's own modules.
    exclude: { path: "(^|/)node_modules/" },
    // `import type` counts: a page's types imported by live/ tie the layers together as much
    // as a value import does.
    tsPreCompilationDeps: true,
    // No tsConfig: the app uses no path aliases, plain relative imports resolve as they are.
    enhancedResolveOptions: {
      extensions: [".ts", ".tsx", ".d.ts", ".js"],
    },
  },
};
