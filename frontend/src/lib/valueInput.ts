// Check what the user typed for an object entry before it goes to the drive, with the same
// rules as the backend's value codec (backend/servodesk/od/values.py): decimal or 0x/0b for
// integers, a hex number on a signed type is the raw register (0xFFFF on INTEGER16 is -1),
// OD low/high limits enforced, hex bytes for octet strings and domains.
import { fixedByteLength, integerType, typeClass } from "./dataTypes";

export type ParsedValue = { ok: true; value: number | string } | { ok: false; error: string };

export interface ValueTarget {
  data_type_name: string;
  low?: number | null;
  high?: number | null;
}

const INT_INPUT = /^([+-]?)(0[xX][0-9A-Fa-f]+|0[bB][01]+|[0-9]+)$/;
const FLOAT_INPUT = /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/;
const REAL32_MAX = 3.4028234663852886e38;
const TRUE_WORDS = new Set(["1", "true", "on", "yes"]);
const FALSE_WORDS = new Set(["0", "false", "off", "no"]);

const fail = (error: string): ParsedValue => ({ ok: false, error });

export function parseValue(text: string, target: ValueTarget): ParsedValue {
  const name = target.data_type_name;
  switch (typeClass(name)) {
    case "text":
      return parseText(text, name);
    case "bytes":
      return parseBytes(text, name);
    case "boolean":
      return parseBoolean(text.trim());
    case "float":
      return parseFloatValue(text.trim(), target);
    case "integer":
      return parseInteger(text.trim(), target);
  }
}

function parseText(text: string, name: string): ParsedValue {
  if (name === "VISIBLE_STRING") {
    const bad = [...new Set(Array.from(text).filter((c) => c < " " || c > "~"))];
    if (bad.length > 0) {
      const shown = bad
        .slice(0, 3)
        .map((c) => JSON.stringify(c))
        .join(", ");
      return fail(`VISIBLE_STRING takes printable ASCII only; remove ${shown}`);
    }
  }
  return { ok: true, value: text };
}

function parseBytes(text: string, name: string): ParsedValue {
  let digits = text.replace(/[\s:_-]/g, "");
  if (digits.slice(0, 2).toLowerCase() === "0x") digits = digits.slice(2);
  if (digits.length % 2 !== 0 || !/^[0-9A-Fa-f]*$/.test(digits)) {
    return fail(`'${text}' is not hex bytes; ${name} takes e.g. 'C8 3D BB'`);
  }
  const bytes = digits.toUpperCase().match(/../g) ?? [];
  const length = fixedByteLength(name);
  if (length !== null && bytes.length !== length) {
    return fail(`${name} is ${length} bytes; got ${bytes.length}`);
  }
  return { ok: true, value: bytes.join(" ") };
}

function parseBoolean(text: string): ParsedValue {
  const lowered = text.toLowerCase();
  if (TRUE_WORDS.has(lowered)) return { ok: true, value: 1 };
  if (FALSE_WORDS.has(lowered)) return { ok: true, value: 0 };
  return fail(`'${text}' is not a BOOLEAN; enter 1/0 or true/false`);
}

function parseFloatValue(text: string, target: ValueTarget): ParsedValue {
  const name = target.data_type_name;
  if (!text) return fail(`Enter a value for ${name}`);
  if (!FLOAT_INPUT.test(text)) return fail(`'${text}' is not a number; ${name} takes e.g. 1.5`);
  const value = Number(text);
  if (!Number.isFinite(value)) return fail(`'${text}' is not a finite number`);
  if (name === "REAL32" && Math.abs(value) > REAL32_MAX) {
    return fail(`${text} is too large for REAL32 (at most 3.402823e38)`);
  }
  return checkLimits(value, target);
}

function parseInteger(text: string, target: ValueTarget): ParsedValue {
  const name = target.data_type_name;
  const type = integerType(name);
  if (!type) return fail(`${name} is not an integer type`);
  const range = `${type.min}..${type.max}`;
  if (!text) return fail(`Enter a value for ${name} (${range})`);
  const match = INT_INPUT.exec(text);
  if (!match) {
    return fail(
      `'${text}' is not a whole number; ${name} takes ${range}, in decimal or hex (0x1F)`,
    );
  }
  const sign = match[1] ?? "";
  const digits = match[2] ?? "0";
  const radixPrefixed = /^0[xXbB]/.test(digits);
  let value = BigInt(digits); // BigInt understands 0x… and 0b… itself
  if (sign === "-") value = -value;
  const modulus = 1n << BigInt(type.bits);
  if (type.signed && radixPrefixed && !sign && value > type.max && value < modulus) {
    value -= modulus; // raw register value, two's complement
  }
  if (value < type.min || value > type.max) {
    return fail(`${value} is out of range for ${name} (${range})`);
  }
  const limited = checkLimits(Number(value), target);
  if (!limited.ok) return limited;
  // Beyond 2^53 a JSON number loses digits; the API parses a decimal string exactly.
  const safe = value >= BigInt(Number.MIN_SAFE_INTEGER) && value <= BigInt(Number.MAX_SAFE_INTEGER);
  return { ok: true, value: safe ? Number(value) : value.toString() };
}

function checkLimits(value: number, target: ValueTarget): ParsedValue {
  const { low, high } = target;
  const bothSet = low != null && high != null;
  if (bothSet && low > high) return { ok: true, value }; // inverted limits in the file: not enforced
  if (low != null && value < low) return fail(`${value} is below the minimum ${low}`);
  if (high != null && value > high) return fail(`${value} is above the maximum ${high}`);
  return { ok: true, value };
}

/** The range hint shown beside an input: OD limits if present, else the type's range. */
export function rangeHint(target: ValueTarget): string {
  const { low, high, data_type_name: name } = target;
  if (low != null || high != null) return `${low ?? "…"} … ${high ?? "…"}`;
  const type = integerType(name);
  if (type) return `${type.min} … ${type.max}`;
  return "";
}
