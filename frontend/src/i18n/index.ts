// The app's languages: English and Simplified Chinese, both catalogues bundled (no loading,
// no suspense), set up on import so every module that translates imports this one. The choice
// is per browser (localStorage); the first visit follows the browser's preferred languages.
import i18n, { type ParseKeys } from "i18next";
import { initReactI18next } from "react-i18next";

import { EN, ZH_CN } from "./catalogues";

export { Trans, useTranslation } from "react-i18next";
export { i18n };

export type Language = "en" | "zh-CN";

/** The select's options, each in its own language so anyone finds theirs. */
export const LANGUAGES: readonly { code: Language; name: string }[] = [
  { code: "en", name: "English" },
  { code: "zh-CN", name: "简体中文" },
];

export const LANGUAGE_STORAGE_KEY = "servodesk.language";

/** Any catalogue key: for label tables (a key per state or kind) that `t()` turns into text. */
export type MessageKey = ParseKeys;

function isLanguage(value: unknown): value is Language {
  return LANGUAGES.some((l) => l.code === value);
}

/** A language tag of the browser's → the app's language; null when the app has none for it. */
function fromTag(tag: string): Language | null {
  const primary = tag.toLowerCase().split(/[-_]/)[0];
  if (primary === "zh") return "zh-CN"; // zh-TW, zh-HK read Simplified better than English
  if (primary === "en") return "en";
  return null;
}

/** The stored choice, else the first of the browser's languages the app speaks, else English. */
export function pickLanguage(stored: string | null, preferred: readonly string[]): Language {
  if (isLanguage(stored)) return stored;
  for (const tag of preferred) {
    const language = fromTag(tag);
    if (language) return language;
  }
  return "en";
}

function storedLanguage(): string | null {
  try {
    return typeof localStorage === "undefined" ? null : localStorage.getItem(LANGUAGE_STORAGE_KEY);
  } catch {
    return null; // storage disabled (privacy mode): the browser's language then
  }
}

function browserLanguages(): readonly string[] {
  if (typeof navigator === "undefined") return []; // Node (unit tests of pure helpers)
  if (navigator.languages.length > 0) return navigator.languages;
  return navigator.language ? [navigator.language] : [];
}

function showLanguage(language: string): void {
  if (typeof document !== "undefined") document.documentElement.lang = language;
}

i18n.on("languageChanged", showLanguage);

void i18n.use(initReactI18next).init({
  resources: { en: { translation: EN }, "zh-CN": { translation: ZH_CN } },
  lng: pickLanguage(storedLanguage(), browserLanguages()),
  fallbackLng: "en",
  supportedLngs: LANGUAGES.map((l) => l.code),
  initAsync: false, // the resources are here: ready before the first render
  returnNull: false,
  interpolation: { escapeValue: false }, // React escapes what it renders
  react: { useSuspense: false },
});

/** The language shown now. */
export function currentLanguage(): Language {
  const language = i18n.resolvedLanguage ?? i18n.language;
  return isLanguage(language) ? language : "en";
}

/** The locale for numbers and dates: "en-US" for English, as the app printed before. */
export function currentLocale(): string {
  return currentLanguage() === "en" ? "en-US" : currentLanguage();
}

/** Switch the app's language now and remember it for this browser. */
export function setLanguage(language: Language): void {
  try {
    localStorage.setItem(LANGUAGE_STORAGE_KEY, language);
  } catch {
    // not remembered, still switched
  }
  void i18n.changeLanguage(language);
}
