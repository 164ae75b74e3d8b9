// Statusword 6041h bit by bit (CiA 402; MDi-S1-C CANopen manual §3.2.3): the generic names,
// the mode-specific meaning of bits 10, 12 and 13, and a tone for each lamp.
import type { StatusBit } from "./types";

export type LampTone = "ok" | "bad" | "warn" | "info";

interface BitDef {
  bit: number;
  name: string;
  /** The tone of the lamp when lit. */
  tone: LampTone;
}

const GENERIC: readonly BitDef[] = [
  { bit: 0, name: "Ready to switch on", tone: "ok" },
  { bit: 1, name: "Switched on", tone: "ok" },
  { bit: 2, name: "Operation enabled", tone: "ok" },
  { bit: 3, name: "Fault", tone: "bad" },
  { bit: 4, name: "Voltage enabled", tone: "ok" },
  { bit: 5, name: "Quick stop (0 = active)", tone: "ok" },
  { bit: 6, name: "Switch on disabled", tone: "info" },
  { bit: 7, name: "Warning", tone: "warn" },
  { bit: 8, name: "Manufacturer specific", tone: "info" },
  { bit: 9, name: "Remote", tone: "ok" },
  { bit: 10, name: "Target reached", tone: "ok" },
  { bit: 11, name: "Internal limit active", tone: "warn" },
  { bit: 12, name: "Operation mode specific", tone: "info" },
  { bit: 13, name: "Operation mode specific", tone: "info" },
  { bit: 14, name: "Manufacturer specific", tone: "info" },
  { bit: 15, name: "Manufacturer specific", tone: "info" },
];

/** Bits 12 and 13 (and 10) per mode, as the manual's table under §3.2.3 names them. */
const MODE_SPECIFIC: Readonly<Record<string, Partial<Record<number, BitDef>>>> = {
  pp: {
    12: { bit: 12, name: "Set-point acknowledge", tone: "info" },
    13: { bit: 13, name: "Following error", tone: "bad" },
  },
  pv: {
    12: { bit: 12, name: "Speed is zero", tone: "info" },
    13: { bit: 13, name: "Max slippage / speed limit", tone: "warn" },
  },
  hm: {
    12: { bit: 12, name: "Homing attained", tone: "ok" },
    13: { bit: 13, name: "Homing error", tone: "bad" },
  },
  ip: {
    12: { bit: 12, name: "Interpolation active", tone: "ok" },
  },
  csp: {
    12: { bit: 12, name: "Drive follows the command", tone: "ok" },
    13: { bit: 13, name: "Following error", tone: "bad" },
  },
};

export interface Lamp {
  bit: number;
  name: string;
  on: boolean;
  tone: LampTone;
}

/** The 16 lamps of a statusword. Names the server sends win over the table's; without them
 * the mode decides what bits 12/13 are called. */
export function statusLamps(
  statusword: number,
  mode: string | null,
  serverBits: readonly StatusBit[] = [],
): Lamp[] {
  const modeBits = mode ? (MODE_SPECIFIC[mode] ?? {}) : {};
  return GENERIC.map((generic) => {
    const def = modeBits[generic.bit] ?? generic;
    const server = serverBits.find((b) => b.bit === def.bit);
    return {
      bit: def.bit,
      name: server && server.name.trim() !== "" ? server.name : def.name,
      on: ((statusword >> def.bit) & 1) === 1,
      tone: def.tone,
    };
  });
}

/** 0x0237 → "0237h". */
export function wordHex(value: number): string {
  return `${(value & 0xffff).toString(16).toUpperCase().padStart(4, "0")}h`;
}

/** The homing progress bits 10/12/13 in words (MDi-S1-C CANopen manual §3.7.1, with the
 * CiA 402 table of homing status combinations). */
export function homingStatus(statusword: number): {
  text: string;
  tone: LampTone;
} {
  const reached = (statusword >> 10) & 1;
  const attained = (statusword >> 12) & 1;
  const error = (statusword >> 13) & 1;
  if (error) return { text: "Homing error", tone: "bad" };
  if (attained && reached) return { text: "Homing attained", tone: "ok" };
  if (attained) return { text: "Homing attained, axis still moving", tone: "info" };
  if (reached) return { text: "Homing interrupted or not started", tone: "warn" };
  return { text: "Homing in progress", tone: "info" };
}
