// The homing words: English as the server sends them, Chinese from the catalogue for the five
// methods drawn, anything else as sent.
import { afterEach, describe, expect, it } from "vitest";

import { i18n } from "../../i18n";
import { methodDescription, methodName, UNTIL, untilWords } from "./homingWords";

afterEach(async () => {
  await i18n.changeLanguage("en");
});

const M17 = { method: 17, name: "Negative limit switch", description: "Searches …" };

describe("homing words", () => {
  it("are the server's in English, and the catalogue's English is the same words", () => {
    expect(methodName(M17)).toBe("Negative limit switch");
    expect(untilWords("home switch rises")).toBe("home switch rises");
    for (const [english, key] of Object.entries(UNTIL)) {
      expect(i18n.t(key, { lng: "en" })).toBe(english);
    }
  });

  it("are the catalogue's in Chinese, and as sent for what the page does not know", async () => {
    await i18n.changeLanguage("zh-CN");
    expect(methodName(M17)).toBe("负限位开关");
    expect(methodDescription({ method: 35, description: "…" })).toBe(
      "轴不运动：当前位置即成为原点（607Ch）。",
    );
    expect(untilWords("home switch falls at its upper edge (home)")).toBe(
      "原点开关在其上沿释放（原点）",
    );
    expect(methodName({ method: 1, name: "Vendor method 1" })).toBe("Vendor method 1");
    expect(untilWords("index pulse")).toBe("index pulse");
  });
});
