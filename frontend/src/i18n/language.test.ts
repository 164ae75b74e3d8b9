import { afterEach, describe, expect, it } from "vitest";

import { currentLanguage, currentLocale, i18n, pickLanguage } from ".";

afterEach(async () => {
  await i18n.changeLanguage("en");
});

describe("pickLanguage", () => {
  it.each([
    // stored, the browser's languages, chosen
    [null, ["en-US", "en"], "en"],
    [null, ["zh-CN", "zh"], "zh-CN"],
    [null, ["zh"], "zh-CN"],
    [null, ["zh-TW", "en"], "zh-CN"],
    [null, ["de-DE", "zh-Hans-CN", "en"], "zh-CN"], // the first the app speaks
    [null, ["en-GB", "zh-CN"], "en"], // English ranked first stays English
    [null, ["fr-FR"], "en"],
    [null, [], "en"],
    ["zh-CN", ["en-US"], "zh-CN"], // the user's choice wins over the browser
    ["en", ["zh-CN"], "en"],
    ["klingon", ["zh-CN"], "zh-CN"], // an unknown stored value is ignored
  ] as const)("stored %s, browser %j → %s", (stored, preferred, chosen) => {
    expect(pickLanguage(stored, preferred)).toBe(chosen);
  });
});

describe("the current language", () => {
  it("is English where the browser has none of the app's (as in Node)", () => {
    expect(currentLanguage()).toBe("en");
    expect(currentLocale()).toBe("en-US");
    expect(i18n.t("nav.network")).toBe("Network");
  });

  it("switches the texts and the number locale", async () => {
    await i18n.changeLanguage("zh-CN");
    expect(currentLanguage()).toBe("zh-CN");
    expect(currentLocale()).toBe("zh-CN");
    expect(i18n.t("nav.network")).toBe("网络");
    expect(i18n.t("network.nodes.found", { count: 1, ms: 9 })).toBe("找到 1 个节点，用时 9 ms");
  });

  it("picks English plural forms by count", () => {
    expect(i18n.t("network.nodes.found", { count: 1, ms: 9 })).toBe("Found 1 node in 9 ms");
    expect(i18n.t("network.nodes.found", { count: 3, ms: 9 })).toBe("Found 3 nodes in 9 ms");
  });
});
