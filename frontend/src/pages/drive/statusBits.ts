// Statusword 6041h bit by bit (CiA 402; MDi-S1-C CANopen manual §3.2.3): the generic names,
// the mode-specific meaning of bits 10, 12 and 13, and a tone for each lamp.
import { currentLanguage, i18n, type MessageKey } from "../../i18n";
import type { StatusBit } from "./types";

export type LampTone = "ok" | "bad" | "warn" | "info";

interface BitDef {
  bit: number;
  name: MessageKey;
  /** The tone of the lamp when lit. */
  tone: LampTone;
}

const GENERIC: readonly BitDef[] = [
  { bit: 0, name: "drive.bit.readyToSwitchOn", tone: "ok" },
  { bit: 1, name: "drive.bit.switchedOn", tone: "ok" },
  { bit: 2, name: "drive.bit.operationEnabled", tone: "ok" },
  { bit: 3, name: "drive.bit.fault", tone: "bad" },
  { bit: 4, name: "drive.bit.voltageEnabled", tone: "ok" },
  { bit: 5, name: "drive.bit.quickStop", tone: "ok" },
  { bit: 6, name: "drive.bit.switchOnDisabled", tone: "info" },
  { bit: 7, name: "drive.bit.warning", tone: "warn" },
  { bit: 8, name: "drive.bit.manufacturer", tone: "info" },
  { bit: 9, name: "drive.bit.remote", tone: "ok" },
  { bit: 10, name: "drive.bit.targetReached", tone: "ok" },
  { bit: 11, name: "drive.bit.internalLimit", tone: "warn" },
  { bit: 12, name: "drive.bit.modeSpecific", tone: "info" },
  { bit: 13, name: "drive.bit.modeSpecific", tone: "info" },
  { bit: 14, name: "drive.bit.manufacturer", tone: "info" },
  { bit: 15, name: "drive.bit.manufacturer", tone: "info" },
];

/** Bits 12 and 13 (and 10) per mode, as the manual's table under §3.2.3 names them. */
const MODE_SPECIFIC: Readonly<Record<string, Partial<Record<number, BitDef>>>> = {
  pp: {
    12: { bit: 12, name: "drive.bit.setPointAck", tone: "info" },
    13: { bit: 13, name: "drive.bit.followingError", tone: "bad" },
  },
  pv: {
    12: { bit: 12, name: "drive.bit.speedZero", tone: "info" },
    13: { bit: 13, name: "drive.bit.maxSlippage", tone: "warn" },
  },
  hm: {
    12: { bit: 12, name: "drive.bit.homingAttained", tone: "ok" },
    13: { bit: 13, name: "drive.bit.homingError", tone: "bad" },
  },
  ip: {
    12: { bit: 12, name: "drive.bit.interpolationActive", tone: "ok" },
  },
  csp: {
    12: { bit: 12, name: "drive.bit.followsCommand", tone: "ok" },
    13: { bit: 13, name: "drive.bit.followingError", tone: "bad" },
  },
};

export interface Lamp {
  bit: number;
  name: string;
  on: boolean;
  tone: LampTone;
}

// The server's own bit names that say more than the table's (servodesk.motion.words), in the
// page's language; another name the server sends shows as sent.
const SERVER_NAMES: Readonly<Record<string, MessageKey>> = {
  "reference found": "drive.bit.server.referenceFound",
  "target position ignored": "drive.bit.server.targetPositionIgnored",
  "max slippage error": "drive.bit.server.maxSlippageError",
  "speed (0 = standstill)": "drive.bit.server.speedStandstill",
};

function serverName(name: string): string {
  if (currentLanguage() === "en") return name;
  const key = SERVER_NAMES[name.trim().toLowerCase()];
  return key ? i18n.t(key) : name;
}

/** Whether the server's name for a bit is shown: in English always (as the drive names it),
 * in another language only where it says more than the table's English name (any case), which
 * is then shown translated. */
function ownName(server: string, key: MessageKey): boolean {
  const name = server.trim().toLowerCase();
  if (name === "") return false;
  return currentLanguage() === "en" || name !== i18n.t(key, { lng: "en" }).toLowerCase();
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
      name: server && ownName(server.name, def.name) ? serverName(server.name) : i18n.t(def.name),
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
  if (error) return { text: i18n.t("drive.homing.error"), tone: "bad" };
  if (attained && reached) return { text: i18n.t("drive.homing.attained"), tone: "ok" };
  if (attained) return { text: i18n.t("drive.homing.attainedMoving"), tone: "info" };
  if (reached) return { text: i18n.t("drive.homing.notStarted"), tone: "warn" };
  return { text: i18n.t("drive.homing.inProgress"), tone: "info" };
}
