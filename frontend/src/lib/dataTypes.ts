// CiA 301 basic data types by the names the API reports (OdEntry.data_type_name).

export type TypeClass = "integer" | "boolean" | "float" | "text" | "bytes";

const SIGNED_BITS: Readonly<Record<string, number>> = {
  INTEGER8: 8,
  INTEGER16: 16,
  INTEGER24: 24,
  INTEGER32: 32,
  INTEGER40: 40,
  INTEGER48: 48,
  INTEGER56: 56,
  INTEGER64: 64,
};

const UNSIGNED_BITS: Readonly<Record<string, number>> = {
  UNSIGNED8: 8,
  UNSIGNED16: 16,
  UNSIGNED24: 24,
  UNSIGNED32: 32,
  UNSIGNED40: 40,
  UNSIGNED48: 48,
  UNSIGNED56: 56,
  UNSIGNED64: 64,
};

const TIME_TYPES: ReadonlySet<string> = new Set(["TIME_OF_DAY", "TIME_DIFFERENCE"]);

export interface IntegerType {
  bits: number;
  signed: boolean;
  min: bigint;
  max: bigint;
}

export function integerType(typeName: string): IntegerType | null {
  const signedBits = SIGNED_BITS[typeName];
  if (signedBits !== undefined) {
    const half = 1n << BigInt(signedBits - 1);
    return { bits: signedBits, signed: true, min: -half, max: half - 1n };
  }
  const unsignedBits = UNSIGNED_BITS[typeName];
  if (unsignedBits !== undefined) {
    return { bits: unsignedBits, signed: false, min: 0n, max: (1n << BigInt(unsignedBits)) - 1n };
  }
  return null;
}

export function typeClass(typeName: string): TypeClass {
  if (typeName === "BOOLEAN") return "boolean";
  if (integerType(typeName)) return "integer";
  if (typeName === "REAL32" || typeName === "REAL64") return "float";
  if (typeName === "VISIBLE_STRING" || typeName === "UNICODE_STRING") return "text";
  // OCTET_STRING, DOMAIN, TIME_* and unknown types travel as hex bytes (docs/api.md).
  return "bytes";
}

/** Byte length a TIME_OF_DAY / TIME_DIFFERENCE value must have, else null. */
export function fixedByteLength(typeName: string): number | null {
  return TIME_TYPES.has(typeName) ? 6 : null;
}
