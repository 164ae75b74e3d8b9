// The server's texts: English as sent, Chinese from the catalogue by message id, the English
// kept for an id the page does not know.
import { afterEach, describe, expect, it } from "vitest";

import { i18n } from "../i18n";
import { serverText } from "./serverText";

const HELD = {
  message: "alice controls this axis now",
  message_id: "reason.held_elsewhere",
  params: { holder: "alice" },
};

afterEach(async () => {
  await i18n.changeLanguage("en");
});

describe("serverText", () => {
  it("is the server's English in English", () => {
    expect(serverText(HELD)).toBe("alice controls this axis now");
  });

  it("is the catalogue's text with the parameters in Chinese", async () => {
    await i18n.changeLanguage("zh-CN");
    expect(serverText(HELD)).toBe("alice 正在控制此轴");
    const mode = {
      message: "…",
      message_id: "reason.mode_refused",
      params: { key: "ip", number: 7 },
    };
    expect(serverText(mode)).toBe(
      "此驱动器不支持模式 ip（7）：驱动器拒绝了它（SDO 中止 06090030h）",
    );
  });

  it("keeps the server's words for an unknown id or none", async () => {
    await i18n.changeLanguage("zh-CN");
    expect(serverText({ message: "new words", message_id: "reason.from_a_newer_server" })).toBe(
      "new words",
    );
    expect(serverText({ message: "plain words" })).toBe("plain words");
  });
});
