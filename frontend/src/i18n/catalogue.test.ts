// The catalogues against each other and against the code: a key the code uses but a catalogue
// lacks would show the bare key to the user, and the typecheck sees only the English catalogue.
import { readFileSync, readdirSync } from "node:fs";
import { join } from "node:path";
import { fileURLToPath } from "node:url";

import { describe, expect, it } from "vitest";

import { EN, ZH_CN } from "./catalogues";

type Catalogue = Record<string, unknown>;

const CATALOGUES: Record<string, Catalogue> = { en: EN, "zh-CN": ZH_CN };
const SRC = fileURLToPath(new URL("..", import.meta.url));
const PLURAL_SUFFIX = /_(zero|one|two|few|many|other)$/;

/** "nav.network" → "Network": every leaf of the nested catalogue under its dotted key. */
function flatten(tree: Catalogue, prefix = ""): Map<string, unknown> {
  const leaves = new Map<string, unknown>();
  for (const [name, value] of Object.entries(tree)) {
    const key = prefix ? `${prefix}.${name}` : name;
    if (typeof value === "object" && value !== null && !Array.isArray(value)) {
      for (const [k, v] of flatten(value as Catalogue, key)) leaves.set(k, v);
    } else {
      leaves.set(key, value);
    }
  }
  return leaves;
}

const FLAT = Object.fromEntries(
  Object.entries(CATALOGUES).map(([language, tree]) => [language, flatten(tree)]),
);
const flatEn = FLAT.en ?? new Map<string, unknown>();

/** Keys as the code names them: a plural's forms ("found_one", "found_other") are one key. */
function baseKeys(flat: Map<string, unknown>): string[] {
  return [...new Set([...flat.keys()].map((k) => k.replace(PLURAL_SUFFIX, "")))].sort();
}

/** The .ts/.tsx files under src/: generated API types left out (no keys there), and this file,
 * whose patterns would match themselves. */
function sourceFiles(): { path: string; text: string }[] {
  return readdirSync(SRC, { recursive: true, encoding: "utf8" })
    .filter((f) => /\.tsx?$/.test(f) && !f.endsWith(".d.ts"))
    .filter((f) => join(SRC, f) !== fileURLToPath(import.meta.url))
    .map((f) => ({ path: f, text: readFileSync(join(SRC, f), "utf8") }));
}

const FILES = sourceFiles();
const NAMESPACES = Object.keys(EN);
/** Every key literal in the code: t("…") / i18n.t("…") / i18nKey="…", and any string literal
 * that starts with a catalogue namespace ("nmt.state.stopped" in a label table, the two keys
 * of a `t(cond ? "a" : "b")`). */
const KEY_PATTERNS = [
  /\bt\(\s*["'`]([^"'`]+)["'`]/g,
  /\bi18nKey=\{?\s*["'`]([^"'`]+)["'`]/g,
  new RegExp(String.raw`["'\`]((?:${NAMESPACES.join("|")})\.[A-Za-z0-9_.]+)["'\`]`, "g"),
];

/** Key → the files that use it. */
function usedKeys(): Map<string, Set<string>> {
  const used = new Map<string, Set<string>>();
  for (const { path, text } of FILES) {
    // tests and the pages' fixtures name files like keys ("drive.eds"): only their t() calls count
    const patterns = /(\.test\.tsx?|(^|\/)fixtures\.ts)$/.test(path)
      ? KEY_PATTERNS.slice(0, 2)
      : KEY_PATTERNS;
    for (const pattern of patterns) {
      for (const match of text.matchAll(pattern)) {
        const key = match[1] ?? "";
        used.set(key, (used.get(key) ?? new Set<string>()).add(path));
      }
    }
  }
  return used;
}

function hasKey(flat: Map<string, unknown>, key: string): boolean {
  return flat.has(key) || [...flat.keys()].some((k) => k.replace(PLURAL_SUFFIX, "") === key);
}

/** "{{node}}", "<node>": what a translation must keep of the English text. */
function placeholders(text: string): string[] {
  return [...text.matchAll(/\{\{\s*(\w+)\s*\}\}|<\/?(\w+)>/g)].map((m) => m[0]).sort();
}

describe("catalogues", () => {
  it("have the same keys in every language", () => {
    const english = baseKeys(flatEn);
    for (const flat of Object.values(FLAT)) expect(baseKeys(flat)).toEqual(english);
  });

  it("have each plural in exactly the forms its language uses", () => {
    for (const [language, flat] of Object.entries(FLAT)) {
      const categories = new Intl.PluralRules(language).resolvedOptions().pluralCategories;
      const plurals = [...flat.keys()].filter((k) => PLURAL_SUFFIX.test(k));
      for (const base of new Set(plurals.map((k) => k.replace(PLURAL_SUFFIX, "")))) {
        const forms = plurals.filter((k) => k.replace(PLURAL_SUFFIX, "") === base);
        expect(forms.sort(), `${language}: ${base}`).toEqual(
          categories.map((c) => `${base}_${c}`).sort(),
        );
      }
    }
  });

  it("have no empty text", () => {
    for (const [language, flat] of Object.entries(FLAT)) {
      for (const [key, value] of flat) {
        expect(typeof value === "string" && value.trim() !== "", `${language}: ${key}`).toBe(true);
      }
    }
  });

  it("keep the English text's placeholders and tags in every translation", () => {
    for (const [language, flat] of Object.entries(FLAT)) {
      for (const [key, value] of flat) {
        const base = key.replace(PLURAL_SUFFIX, "");
        const english = flatEn.get(key) ?? flatEn.get(`${base}_other`);
        expect(placeholders(String(value)), `${language}: ${key}`).toEqual(
          placeholders(String(english)),
        );
      }
    }
  });
});

describe("keys the code uses", () => {
  const used = usedKeys();

  it("are found in the source", () => {
    // the scan itself works: the shell and the Network page use well over a hundred
    expect(used.size).toBeGreaterThan(100);
    expect(used.has("nav.network")).toBe(true);
  });

  it("are in every catalogue", () => {
    for (const [language, flat] of Object.entries(FLAT)) {
      const missing = [...used]
        .filter(([key]) => !hasKey(flat, key))
        .map(([key, files]) => `${key} (${[...files].join(", ")})`);
      expect(missing, language).toEqual([]);
    }
  });

  it("are literals, so the scan above sees them all", () => {
    const dynamic = FILES.flatMap(({ path, text }) =>
      [...text.matchAll(/\bt\(\s*`[^`]*\$\{/g)].map(() => path),
    );
    expect(dynamic).toEqual([]);
  });
});
