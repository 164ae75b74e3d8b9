import { describe, expect, it } from "vitest";

import type { Fault } from "../api/faults";
import {
  bannerText,
  checkParts,
  faultCheckParts,
  errorCodeParts,
  errorRegisterText,
  errorRegisterWords,
  faultCode,
  faultName,
  faultWords,
  hasNoObject,
  isTranslatedName,
  nameSource,
  newestFirst,
  sourceLabel,
  stateChange,
} from "./faultText";

function fault(overrides: Partial<Fault> = {}): Fault {
  return {
    time: 1_700_000_000,
    node: 1,
    code: 4,
    code_hex: "0x0004",
    source: "vendor",
    name_en: "Following error",
    name_zh: "位置超差",
    check: null,
    error_register: null,
    manufacturer_hex: null,
    raw_hex: "04 00",
    ...overrides,
  };
}

describe("error register", () => {
  it.each([
    [0x00, []],
    [0x01, ["generic"]],
    [0x21, ["generic", "device profile"]],
    [0x81, ["generic", "manufacturer"]],
    [
      0xff,
      [
        "generic",
        "current",
        "voltage",
        "temperature",
        "communication",
        "device profile",
        "reserved bit 6",
        "manufacturer",
      ],
    ],
  ])("%i in words", (register, words) => {
    expect(errorRegisterWords(register)).toEqual(words);
  });

  it.each([
    [null, "—"],
    [undefined, "—"],
    [0, "00h: no error"],
    [0x21, "21h: generic, device profile"],
    [0x11, "11h: generic, communication"],
  ])("%s as text", (register, text) => {
    expect(errorRegisterText(register)).toBe(text);
  });
});

describe("fault words", () => {
  it.each([
    [fault(), "alarm 4", "alarm 4 位置超差 Following error"],
    [
      fault({ code: 0x8611, code_hex: "0x8611", name_zh: null }),
      "0x8611",
      "0x8611 Following error",
    ],
    [
      fault({ code: 0x8611, code_hex: "0x8611", source: "cia402", name_zh: null }),
      "0x8611",
      "0x8611 Following error",
    ],
    [
      fault({
        code: 61,
        code_hex: "0x003D",
        source: "unknown",
        name_zh: null,
        name_en: "Unknown alarm 61",
      }),
      "0x003D",
      "0x003D Unknown alarm 61",
    ],
  ])("%#", (f, code, words) => {
    expect(faultCode(f)).toBe(code);
    expect(faultWords(f)).toBe(words);
  });

  it("makes the banner line", () => {
    expect(bannerText(fault())).toBe("Node 1 in fault: alarm 4 位置超差 Following error");
  });

  it.each([
    ["vendor", "the drive's own alarm table"],
    ["cia402", "CiA 402 (drive profile)"],
    ["cia301", "CiA 301 (communication)"],
    ["unknown", "not in any table"],
    ["other", "other"],
  ])("source %s", (source, label) => {
    expect(sourceLabel(source)).toBe(label);
  });
});

describe("checkParts", () => {
  it.each([
    [null, []],
    ["", []],
    ["Check the wiring.", [{ label: "", key: "", text: "Check the wiring." }]],
    [
      "Cause: position deviation too large. Check: gain, load, 6065h. CiA code 8611h: Following error. Source: MDi-S1-C CANopen manual §4.1.",
      [
        { label: "Cause", key: "cause", text: "position deviation too large." },
        { label: "Check", key: "check", text: "gain, load, 6065h." },
        { label: "CiA code 8611h", key: "", text: "Following error." },
        { label: "Source", key: "source", text: "MDi-S1-C CANopen manual §4.1." },
      ],
    ],
    [
      "CiA class: Monitoring. Error register 21h: generic, device profile.",
      [
        { label: "CiA class", key: "", text: "Monitoring." },
        { label: "Error register 21h", key: "", text: "generic, device profile." },
      ],
    ],
    [
      "Cause: x. The EMCY carries only the low 16 bits of 603Fh (12320h, 22320h share them): read 603Fh. Check: a. Check: b.",
      [
        {
          label: "Cause",
          key: "cause",
          text: "x. The EMCY carries only the low 16 bits of 603Fh (12320h, 22320h share them): read 603Fh.",
        },
        { label: "Check", key: "check", text: "a." },
        { label: "Check", key: "check", text: "b." },
      ],
    ],
  ])("%#", (check, parts) => {
    expect(checkParts(check)).toEqual(parts);
  });

  it("splits the server's Chinese text at its Chinese labels, in Chinese only", () => {
    const fault = {
      check: "Cause: x. Source: Kinco servo CANopen manual §8.",
      check_zh: "原因：位置误差过大。 CiA 代码 8611h：跟随误差。 来源：步科伺服 CANopen 手册 §8。",
    };
    expect(faultCheckParts(fault, "zh-CN")).toEqual([
      { label: "原因", key: "cause", text: "位置误差过大。" },
      { label: "CiA 代码 8611h", key: "", text: "跟随误差。" },
      { label: "来源", key: "source", text: "步科伺服 CANopen 手册 §8。" },
    ]);
    expect(faultCheckParts(fault, "en").map((part) => part.key)).toEqual(["cause", "source"]);
    expect(faultCheckParts({ ...fault, check_zh: null }, "zh-CN")[0]?.label).toBe("Cause");
  });
});

describe("newestFirst", () => {
  it("sorts by time, keeping the order of equal times", () => {
    const items = [
      { time: 1, id: "a" },
      { time: 3, id: "b" },
      { time: 3, id: "c" },
      { time: 2, id: "d" },
    ];
    expect(newestFirst(items).map((i) => i.id)).toEqual(["b", "c", "d", "a"]);
  });
});

describe("603Fh and states", () => {
  it.each([
    [0, null, { hex: "0x0000", words: "no error" }],
    [4, fault(), { hex: "0x0004", words: "alarm 4 位置超差 Following error" }],
    [5, fault(), { hex: "0x0005", words: null }],
    [
      0x8611,
      fault({ code: 0x8611, code_hex: "0x8611", name_zh: null }),
      { hex: "0x8611", words: "Following error" },
    ],
    [
      0x2320,
      fault({ code: 0x12320, code_hex: "0x12320", source: "vendor" }),
      { hex: "0x2320", words: "0x12320 位置超差 Following error" },
    ],
    ["n/a", null, { hex: "n/a", words: null }],
    [null, null, { hex: "—", words: null }],
  ])("603Fh %s", (value, active, parts) => {
    expect(errorCodeParts(value, active)).toEqual(parts);
  });

  it.each([
    [{ state_before: "Operation enabled", state_after: "Fault" }, "Operation enabled → Fault"],
    [{ state_before: null, state_after: "Fault" }, "not seen → Fault"],
    [{}, "—"],
  ])("state change %#", (states, text) => {
    expect(stateChange(states)).toBe(text);
  });

  it.each([
    ["0x06020000", true],
    ["06090011", true],
    ["0x06010002", false],
    [null, false],
  ])("no such object: %s", (code, answer) => {
    expect(hasNoObject(code)).toBe(answer);
  });
});

describe("fault names", () => {
  const kinco = fault({
    code: 0x8611,
    code_hex: "0x8611",
    name_en: "Following error too high",
    name_zh: "跟随误差过大",
    name_zh_source: "translation",
    check: "Cause: x. Source: ServoDesk's simulated drive; the Kinco manual marks it not used.",
  });

  it("shows the manual's Chinese in both languages, a translation only in Chinese", () => {
    const mdi = fault({ name_zh_source: "manual" });
    expect(faultName(mdi, "en")).toBe("位置超差 Following error");
    expect(faultName(mdi, "zh-CN")).toBe("位置超差");
    expect(faultName(kinco, "en")).toBe("Following error too high");
    expect(faultName(kinco, "zh-CN")).toBe("跟随误差过大");
    expect(faultName(fault({ name_zh: null }), "zh-CN")).toBe("Following error");
    // stored before the source was recorded: only the MDi's manual had Chinese then
    expect(faultName(fault({ name_zh_source: null }), "en")).toBe("位置超差 Following error");
  });

  it("tells a translation and its source table", () => {
    expect(isTranslatedName(kinco)).toBe(true);
    expect(isTranslatedName(fault({ name_zh_source: "manual" }))).toBe(false);
    expect(nameSource(kinco)).toBe("ServoDesk's simulated drive");
    expect(nameSource(fault({ source: "cia301", check: null }))).toBe("CiA 301 (communication)");
  });
});
