// The translated pages' tests render in Simplified Chinese; each test leaves the language
// (English) and the globals as it found them for the next.
import { afterEach, beforeEach, vi } from "vitest";

import { i18n } from "../i18n";

/** Every test of the calling file runs in zh-CN. */
export function inChinese(): void {
  beforeEach(async () => {
    await i18n.changeLanguage("zh-CN");
  });
  afterEach(async () => {
    vi.unstubAllGlobals();
    await i18n.changeLanguage("en");
  });
}
