/// <reference types="vitest/config" />
// One config for the dev server, the production build and the unit tests. The npm scripts run
// from the repository root, so every path here is anchored to this file, not to the cwd.
import { availableParallelism } from "node:os";

import react from "@vitejs/plugin-react";
import { defineConfig } from "vite";

const here = decodeURIComponent(new URL(".", import.meta.url).pathname);
const backend = "http://127.0.0.1:8000";
// .ts tests that need a browser's globals (the others run in plain Node)
const BROWSER_GLOBALS = [
  "src/api/errors.test.ts",
  "src/live/connection.test.ts",
  "src/pages/scope/rerunViewer.test.ts",
];

export default defineConfig({
  root: here,
  base: "/",
  plugins: [react()],
  build: {
    // The backend serves this folder: /assets/* as files, every other path falls back to
    // index.html so the browser's own routes (/nodes/1/od) survive a reload.
    outDir: `${here}../backend/servodesk/static`,
    emptyOutDir: true,
    assetsDir: "assets",
    sourcemap: false,
  },
  server: {
    proxy: {
      "/api": { target: backend, ws: true },
      // rerun's viewer and its gRPC-web stream, both served through the backend
      "/rerun/": { target: backend },
      "/rerun.sdk_comms.v1alpha1.MessageProxyService": { target: backend },
    },
  },
  test: {
    root: here,
    restoreMocks: true,
    // Vitest keeps a core free by default: one worker on a 2-core machine, half the speed
    maxWorkers: Math.max(2, availableParallelism() - 1),
    testTimeout: 20000, // a 2-core machine running the browser tests beside: see setup.ts
    // Pure logic runs in Node; only what renders or needs the browser's globals (fetch,
    // WebSocket, window) pays for a jsdom window per file (most of the run's time before).
    projects: [
      {
        extends: true,
        test: {
          name: "logic",
          environment: "node",
          include: ["src/**/*.test.ts"],
          exclude: BROWSER_GLOBALS,
        },
      },
      {
        extends: true,
        test: {
          name: "dom",
          environment: "jsdom",
          include: ["src/**/*.test.tsx", ...BROWSER_GLOBALS],
          setupFiles: ["src/test/setup.ts"],
          // One jsdom window per worker, not per file (its set-up was half the run's time):
          // setup.ts cleans up what one test leaves (the tree, the language, the storage)
          isolate: false,
        },
      },
    ],
  },
});
