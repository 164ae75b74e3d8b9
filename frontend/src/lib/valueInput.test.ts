import { describe, expect, it } from "vitest";

import { parseValue, rangeHint } from "./valueInput";

const ok = (value: number | string) => ({ ok: true, value });

describe("parseValue: integers", () => {
  it.each([
    ["UNSIGNED8", "255", ok(255)],
    ["UNSIGNED8", "0xFF", ok(255)],
    ["UNSIGNED8", "0b101", ok(5)],
    ["UNSIGNED16", " 0x1f ", ok(31)],
    ["INTEGER8", "-128", ok(-128)],
    ["INTEGER8", "127", ok(127)],
    ["INTEGER16", "-5", ok(-5)],
    ["INTEGER16", "0xFFFF", ok(-1)], // hex on a signed type is the raw register
    ["INTEGER32", "0x80000000", ok(-2147483648)],
    ["INTEGER32", "-0x10", ok(-16)],
    ["UNSIGNED32", "4294967295", ok(4294967295)],
    ["UNSIGNED64", "18446744073709551615", ok("18446744073709551615")], // beyond 2^53: as text
    ["INTEGER64", "-9223372036854775808", ok("-9223372036854775808")],
    ["BOOLEAN", "true", ok(1)],
    ["BOOLEAN", "0", ok(0)],
  ])("%s %j", (type, text, expected) => {
    expect(parseValue(text, { data_type_name: type })).toEqual(expected);
  });

  it.each([
    ["UNSIGNED8", "256", "out of range for UNSIGNED8 (0..255)"],
    ["UNSIGNED8", "-1", "out of range for UNSIGNED8"],
    ["UNSIGNED16", "0x10000", "out of range"],
    ["INTEGER8", "128", "out of range for INTEGER8 (-128..127)"],
    ["INTEGER16", "0x1FFFF", "out of range"],
    ["INTEGER32", "1.5", "not a whole number"],
    ["UNSIGNED32", "", "Enter a value"],
    ["UNSIGNED32", "12abc", "not a whole number"],
    ["BOOLEAN", "maybe", "not a BOOLEAN"],
  ])("%s rejects %j", (type, text, message) => {
    const result = parseValue(text, { data_type_name: type });
    expect(result.ok).toBe(false);
    if (!result.ok) expect(result.error).toContain(message);
  });

  it("enforces the dictionary's low/high limits", () => {
    const entry = { data_type_name: "UNSIGNED16", low: 10, high: 1000 };
    expect(parseValue("10", entry)).toEqual(ok(10));
    expect(parseValue("9", entry)).toMatchObject({ ok: false, error: "9 is below the minimum 10" });
    expect(parseValue("0x3E9", entry)).toMatchObject({
      ok: false,
      error: "1001 is above the maximum 1000",
    });
  });

  it("ignores inverted limits (reported at import, not enforced)", () => {
    expect(parseValue("5", { data_type_name: "UNSIGNED8", low: 100, high: 1 })).toEqual(ok(5));
  });
});

describe("parseValue: floats, strings, bytes", () => {
  it("reads REAL32 numbers and refuses what does not fit", () => {
    expect(parseValue("1.5", { data_type_name: "REAL32" })).toEqual(ok(1.5));
    expect(parseValue("-2e3", { data_type_name: "REAL64" })).toEqual(ok(-2000));
    expect(parseValue("1e39", { data_type_name: "REAL32" }).ok).toBe(false);
    expect(parseValue("abc", { data_type_name: "REAL32" }).ok).toBe(false);
    expect(parseValue("0.5", { data_type_name: "REAL32", high: 0.25 }).ok).toBe(false);
  });

  it("passes visible strings through and refuses control characters", () => {
    expect(parseValue("C5-E drive", { data_type_name: "VISIBLE_STRING" })).toEqual(
      ok("C5-E drive"),
    );
    const bad = parseValue("tab\there", { data_type_name: "VISIBLE_STRING" });
    expect(bad).toMatchObject({ ok: false });
    expect(parseValue("température", { data_type_name: "UNICODE_STRING" })).toEqual(
      ok("température"),
    );
  });

  it("normalises hex bytes for octet strings and domains", () => {
    expect(parseValue("c8 3d bb", { data_type_name: "OCTET_STRING" })).toEqual(ok("C8 3D BB"));
    expect(parseValue("0xC83DBB", { data_type_name: "DOMAIN" })).toEqual(ok("C8 3D BB"));
    expect(parseValue("C8:3D", { data_type_name: "OCTET_STRING" })).toEqual(ok("C8 3D"));
    expect(parseValue("C8 3", { data_type_name: "OCTET_STRING" }).ok).toBe(false);
    expect(parseValue("zz", { data_type_name: "DOMAIN" }).ok).toBe(false);
    expect(parseValue("01 02 03", { data_type_name: "TIME_OF_DAY" })).toMatchObject({
      ok: false,
      error: "TIME_OF_DAY is 6 bytes; got 3",
    });
  });
});

describe("rangeHint", () => {
  it("shows the dictionary limits, else the type's range", () => {
    expect(rangeHint({ data_type_name: "INTEGER8" })).toBe("-128 … 127");
    expect(rangeHint({ data_type_name: "UNSIGNED16", low: 1, high: 500 })).toBe("1 … 500");
    expect(rangeHint({ data_type_name: "VISIBLE_STRING" })).toBe("");
  });
});
