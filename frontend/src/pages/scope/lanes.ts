// Which statusword / controlword bits get a lane of their own in the capture's recording
// (under the CiA 402 state or the controlword's command). Kept in this tab's session storage
// like the rest of the form. Pure but for load/save.
import type { MessageKey } from "../../i18n";
import type { LanesRequest } from "./types";

export interface Lanes {
  statusword_bits: number[];
  controlword_bits: number[];
}

/** CiA 402 names; 12/13 mean what the mode says, both main meanings given. */
export const STATUSWORD_BITS: readonly (readonly [number, MessageKey])[] = [
  [0, "scope.lanes.status.b0"],
  [1, "scope.lanes.status.b1"],
  [2, "scope.lanes.status.b2"],
  [3, "scope.lanes.status.b3"],
  [4, "scope.lanes.status.b4"],
  [5, "scope.lanes.status.b5"],
  [6, "scope.lanes.status.b6"],
  [7, "scope.lanes.status.b7"],
  [9, "scope.lanes.status.b9"],
  [10, "scope.lanes.status.b10"],
  [11, "scope.lanes.status.b11"],
  [12, "scope.lanes.status.b12"],
  [13, "scope.lanes.status.b13"],
];
export const CONTROLWORD_BITS: readonly (readonly [number, MessageKey])[] = [
  [0, "scope.lanes.control.b0"],
  [1, "scope.lanes.control.b1"],
  [2, "scope.lanes.control.b2"],
  [3, "scope.lanes.control.b3"],
  [4, "scope.lanes.control.b4"],
  [5, "scope.lanes.control.b5"],
  [6, "scope.lanes.control.b6"],
  [7, "scope.lanes.control.b7"],
  [8, "scope.lanes.control.b8"],
];

export const DEFAULT_LANES: Lanes = {
  statusword_bits: [3, 7, 10, 11, 12, 13],
  controlword_bits: [0, 1, 2, 3, 4, 7, 8],
};

/** The bits with `bit` switched on or off, in order. */
export function toggleBit(bits: readonly number[], bit: number): number[] {
  const next = bits.includes(bit) ? bits.filter((b) => b !== bit) : [...bits, bit];
  return next.sort((x, y) => x - y);
}

const bitsOf = (value: unknown, fallback: number[]): number[] =>
  Array.isArray(value)
    ? [...new Set(value.filter((b): b is number => Number.isInteger(b) && b >= 0 && b <= 15))].sort(
        (x, y) => x - y,
      )
    : fallback;

/** Stored lanes back; anything unreadable falls back to the defaults. */
export function parseLanes(stored: string | null): Lanes {
  let data: unknown;
  try {
    data = stored ? JSON.parse(stored) : null;
  } catch {
    return DEFAULT_LANES;
  }
  if (typeof data !== "object" || data === null) return DEFAULT_LANES;
  const record = data as Record<string, unknown>;
  return {
    statusword_bits: bitsOf(record.statusword_bits, DEFAULT_LANES.statusword_bits),
    controlword_bits: bitsOf(record.controlword_bits, DEFAULT_LANES.controlword_bits),
  };
}

const KEY = "servodesk.scope.lanes";

export function loadLanes(): Lanes {
  try {
    return parseLanes(sessionStorage.getItem(KEY));
  } catch {
    return DEFAULT_LANES;
  }
}

export function saveLanes(lanes: Lanes): void {
  try {
    sessionStorage.setItem(KEY, JSON.stringify(lanes));
  } catch {
    // storage full or off: the choice lasts until the tab closes
  }
}

/** Whether the capture will carry a word that gets lanes (picked, or added for a trigger). */
export function hasWord(indexes: readonly number[], triggerKind: string): boolean {
  return indexes.some((i) => i === 0x6041 || i === 0x6040) || triggerKind === "state";
}

export function asRequest(lanes: Lanes): LanesRequest {
  return { statusword_bits: lanes.statusword_bits, controlword_bits: lanes.controlword_bits };
}
