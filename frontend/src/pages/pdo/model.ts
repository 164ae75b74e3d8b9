// Pure PDO helpers: the byte layout of a frame, what fits, transmission types in words and
// what a draft changes against the device. No I/O; table-tested in model.test.ts.
import { i18n } from "../../i18n";
import { integerType } from "../../lib/dataTypes";
import { formatCobId, formatPercent, formatRate, odAddress } from "../../lib/format";
import { serverText, type TextParams } from "../../lib/serverText";
import type { MappedObject, Pdo, PdoKind, PdoRules, Problem } from "./types";

// In lib/format.ts (the Scope page and components/LoadBar.tsx use them too); re-exported here
// for this page's callers.
export { formatCobId, formatPercent, formatRate };

export const MAX_BITS = 64; // one classic CAN frame
export const MAX_ENTRIES = 8; // mapping sub 0 range 0–8

/** What the dictionary says about one mappable object (from the OD tree). */
export interface ObjectInfo {
  index: number;
  subindex: number;
  name: string;
  unit: string;
  access: string;
  dataTypeName: string;
  /** Size in bits; null for types without a fixed size (strings, domains). */
  bits: number | null;
  mappable: boolean;
}

export type Lookup = (index: number, subindex: number) => ObjectInfo | undefined;

export function pdoKey(pdo: { kind: PdoKind; number: number }): string {
  return `${pdo.kind}${pdo.number}`;
}

/** "RPDO1" / "TPDO3" as the manuals name them. */
export function pdoLabel(pdo: { kind: PdoKind; number: number }): string {
  return `${pdo.kind.toUpperCase()}${pdo.number}`;
}

/** The communication / mapping parameter indices of a PDO: "1800h / 1A00h". */
export function pdoObjects(pdo: { kind: PdoKind; number: number }): string {
  const comm = commIndex(pdo);
  return `${odAddress(comm)} / ${odAddress(comm + 0x200)}`;
}

/** A CAN identifier as typed: "0x181", "181h" or "181" (hex, as the manuals print it). */
export function parseCobId(text: string): number | null {
  const cleaned = text.trim().replace(/^0x/i, "").replace(/h$/i, "");
  if (!/^[0-9a-f]{1,3}$/i.test(cleaned)) return null;
  const value = Number.parseInt(cleaned, 16);
  return value >= 1 && value <= 0x7ff ? value : null;
}

/** Inhibit time: the object counts 100 µs, people read milliseconds. */
export function inhibitMs(value100us: number): number {
  return value100us / 10;
}

export function inhibitFromMs(ms: number): number {
  return Math.round(ms * 10);
}

const ORDINALS = {
  st: "pdo.transmission.ordinal.st",
  nd: "pdo.transmission.ordinal.nd",
  rd: "pdo.transmission.ordinal.rd",
  th: "pdo.transmission.ordinal.th",
} as const;

function ordinal(n: number): string {
  const suffix =
    n % 100 >= 10 && n % 100 <= 20
      ? "th"
      : (({ 1: "st", 2: "nd", 3: "rd" } as const)[n % 10] ?? "th");
  return i18n.t(ORDINALS[suffix], { n });
}

/** A problem (or SYNC warning) of the server's in the page's language; a synchronous PDO's
 * transmission type in the page's own words. */
export function problemText(problem: Problem): string {
  const t = problem.params?.t;
  const words: TextParams =
    typeof t === "number" ? { words: transmissionWords(t, problem.kind) } : {};
  return serverText(problem, words);
}

/** A transmission type in words (CiA 301 §7.5.2.35), used when the server sends none. */
export function transmissionWords(type: number, kind: PdoKind): string {
  const tpdo = kind === "tpdo";
  const t = i18n.t;
  if (type === 0) {
    return tpdo ? t("pdo.transmission.syncAcyclicTpdo") : t("pdo.transmission.syncAcyclicRpdo");
  }
  if (type === 1) return t("pdo.transmission.everySync");
  if (type <= 240) {
    return tpdo
      ? t("pdo.transmission.everyNthSync", { nth: ordinal(type) })
      : t("pdo.transmission.synchronous");
  }
  if (type === 252) return t("pdo.transmission.rtrSampled");
  if (type === 253) return t("pdo.transmission.rtr");
  if (type === 254 || type === 255) {
    const which = type === 254 ? t("pdo.transmission.manufacturer") : t("pdo.transmission.profile");
    return tpdo
      ? t("pdo.transmission.eventTpdo", { which })
      : t("pdo.transmission.eventRpdo", { which });
  }
  return t("pdo.transmission.reserved", { type });
}

/** Types 0–240 and 252 act on SYNC: they need a SYNC producer on the bus. */
export function isSynchronous(type: number): boolean {
  return type <= 240 || type === 252;
}

/** Transmission types offered in the editor, by kind. */
export function transmissionChoices(kind: PdoKind): number[] {
  return kind === "tpdo" ? [0, 1, 2, 5, 10, 252, 253, 254, 255] : [0, 1, 254, 255];
}

/** Bits of an OD data type, or null when it has no fixed size. */
export function typeBits(dataTypeName: string): number | null {
  if (dataTypeName === "BOOLEAN") return 1;
  const int = integerType(dataTypeName);
  if (int) return int.bits;
  if (dataTypeName === "REAL32") return 32;
  if (dataTypeName === "REAL64") return 64;
  return null;
}

export function isWritable(access: string): boolean {
  return access.includes("w");
}

export function isReadable(access: string): boolean {
  return access.includes("r") || access === "const";
}

export interface LayoutBlock {
  /** Position in the mapping (0-based). */
  position: number;
  index: number;
  subindex: number;
  bits: number;
  startBit: number;
  /** Past the 64-bit frame: the mapping does not fit. */
  overflow: boolean;
  /** The dictionary's name, else the server's, else null (shown raw as index:sub). */
  name: string | null;
  unit: string;
  known: boolean;
}

export interface Layout {
  blocks: LayoutBlock[];
  usedBits: number;
  /** Bytes the frame carries (DLC). */
  bytes: number;
}

/** Where each mapped object sits in the frame: packed little-endian, one after the other. */
export function frameLayout(mapping: readonly MappedObject[], lookup: Lookup): Layout {
  let start = 0;
  const blocks = mapping.map((entry, position): LayoutBlock => {
    const info = lookup(entry.index, entry.subindex);
    const block: LayoutBlock = {
      position,
      index: entry.index,
      subindex: entry.subindex,
      bits: entry.bits,
      startBit: start,
      overflow: start + entry.bits > MAX_BITS,
      name: info?.name ?? entry.name ?? null,
      unit: info?.unit ?? "",
      known: info !== undefined,
    };
    start += entry.bits;
    return block;
  });
  return { blocks, usedBits: start, bytes: Math.ceil(start / 8) };
}

export function usedBits(mapping: readonly MappedObject[]): number {
  return mapping.reduce((sum, entry) => sum + entry.bits, 0);
}

export interface FitRules {
  /** The drive maps whole bytes only (MDi-S1-C, Kinco). */
  byteGranular: boolean;
  /** PDOs 1..n keep their pre-defined CAN id (0: every COB-ID can change). */
  fixedCobIds: number;
}

/** What the browser checks before asking the server, from the node's rules (permissive
 * while they load: the server's validation still catches what they would have). */
export function fitRules(rules: PdoRules | undefined): FitRules {
  return { byteGranular: rules?.byte_granular ?? false, fixedCobIds: rules?.fixed_cob_ids ?? 0 };
}

/** Why the COB-ID of `pdo` cannot change on this drive; null when it can. */
export function fixedCobIdReason(pdo: { number: number }, rules: FitRules): string | null {
  const n = rules.fixedCobIds;
  if (n <= 0 || pdo.number > n) return null;
  return n === 1 ? i18n.t("pdo.fit.fixedCobIdOne") : i18n.t("pdo.fit.fixedCobIdMany", { n });
}

/** Why `object` cannot be added to `pdo`, in words; null when it fits. */
export function fitProblem(pdo: Pdo, object: ObjectInfo, rules: FitRules): string | null {
  const t = i18n.t;
  const what = `${object.name} (${odAddress(object.index, object.subindex)})`;
  if (!object.mappable) return t("pdo.fit.notMappable", { what });
  if (object.bits === null) return t("pdo.fit.noSize", { what, type: object.dataTypeName });
  if (pdo.kind === "rpdo" && !isWritable(object.access)) {
    return t("pdo.fit.rpdoReadOnly", { what });
  }
  if (pdo.kind === "tpdo" && !isReadable(object.access)) {
    return t("pdo.fit.tpdoWriteOnly", { what });
  }
  if (rules.byteGranular && object.bits % 8 !== 0) {
    return t("pdo.fit.wholeBytes", { what, bits: object.bits });
  }
  if (pdo.mapping.length >= MAX_ENTRIES) {
    return t("pdo.fit.full", { label: pdoLabel(pdo), max: MAX_ENTRIES });
  }
  const used = usedBits(pdo.mapping);
  if (used + object.bits > MAX_BITS) {
    return t("pdo.fit.tooBig", {
      what,
      bits: object.bits,
      label: pdoLabel(pdo),
      left: MAX_BITS - used,
      max: MAX_BITS,
    });
  }
  return null;
}

/** The communication parameter fields a problem can name, by subindex (CiA 301 §7.5.2.35). */
export type CommField =
  "cob_id" | "transmission_type" | "inhibit_time" | "event_timer" | "sync_start";

const COMM_FIELDS: Readonly<Record<number, CommField>> = {
  1: "cob_id",
  2: "transmission_type",
  3: "inhibit_time",
  5: "event_timer",
  6: "sync_start",
};

export function commIndex(pdo: { kind: PdoKind; number: number }): number {
  return (pdo.kind === "rpdo" ? 0x1400 : 0x1800) + pdo.number - 1;
}

/** A PDO's problems by where they are shown: at a mapped object in the frame (by mapping
 * position), at a communication parameter field, or under the PDO (`rest`). */
export interface PlacedProblems {
  atEntry: Map<number, Problem[]>;
  atField: Map<CommField, Problem[]>;
  rest: Problem[];
}

export function placeProblems(pdo: Pdo, problems: readonly Problem[]): PlacedProblems {
  const placed: PlacedProblems = { atEntry: new Map(), atField: new Map(), rest: [] };
  const add = <K>(map: Map<K, Problem[]>, key: K, problem: Problem): void => {
    map.set(key, [...(map.get(key) ?? []), problem]);
  };
  const comm = commIndex(pdo);
  for (const problem of problems) {
    const { index, subindex } = problem;
    if (index == null) {
      placed.rest.push(problem);
      continue;
    }
    const sub = subindex ?? 0;
    const positions = pdo.mapping
      .map((e, i) => (e.index === index && e.subindex === sub ? i : -1))
      .filter((i) => i >= 0);
    const field = index === comm ? COMM_FIELDS[sub] : undefined;
    if (positions.length > 0) {
      for (const position of positions) add(placed.atEntry, position, problem);
    } else if (index === comm + 0x200 && sub >= 1 && sub <= pdo.mapping.length) {
      add(placed.atEntry, sub - 1, problem); // a mapping entry (1A00h:02 is the 2nd object)
    } else if (field) {
      add(placed.atField, field, problem);
    } else {
      placed.rest.push(problem);
    }
  }
  return placed;
}

/** The mapping with the entry at `from` moved to `to` (both clamped). */
export function moveEntry<T>(list: readonly T[], from: number, to: number): T[] {
  const out = [...list];
  if (from < 0 || from >= out.length) return out;
  const target = Math.max(0, Math.min(out.length - 1, to));
  const [item] = out.splice(from, 1);
  if (item !== undefined) out.splice(target, 0, item);
  return out;
}

export function sameMapping(a: readonly MappedObject[], b: readonly MappedObject[]): boolean {
  const key = (e: MappedObject): string => `${e.index}:${e.subindex}:${e.bits}`;
  return a.map(key).join(",") === b.map(key).join(",");
}

/** What the draft changes on one PDO, in words; empty when nothing. */
export function pdoChanges(before: Pdo | undefined, after: Pdo): string[] {
  const t = i18n.t;
  if (!before) return [t("pdo.change.newPdo")];
  const out: string[] = [];
  if (before.cob_id !== after.cob_id) {
    out.push(`COB-ID ${formatCobId(before.cob_id)} → ${formatCobId(after.cob_id)}`);
  }
  if (before.valid !== after.valid) {
    out.push(after.valid ? t("pdo.change.madeValid") : t("pdo.change.madeInvalid"));
  }
  if (before.transmission_type !== after.transmission_type) {
    out.push(
      t("pdo.change.transmission", {
        from: before.transmission_type,
        to: after.transmission_type,
        words: transmissionWords(after.transmission_type, after.kind),
      }),
    );
  }
  if (before.inhibit_time_100us !== after.inhibit_time_100us) {
    out.push(
      t("pdo.change.inhibit", {
        from: inhibitMs(before.inhibit_time_100us),
        to: inhibitMs(after.inhibit_time_100us),
      }),
    );
  }
  if (before.event_timer_ms !== after.event_timer_ms) {
    out.push(t("pdo.change.eventTimer", { from: before.event_timer_ms, to: after.event_timer_ms }));
  }
  if (before.sync_start !== after.sync_start) {
    out.push(t("pdo.change.syncStart", { from: before.sync_start, to: after.sync_start }));
  }
  if (!sameMapping(before.mapping, after.mapping)) {
    const names = after.mapping.map((e) => e.name ?? odAddress(e.index, e.subindex));
    const objects = names.length ? names.join(t("common.listSeparator")) : t("pdo.change.nothing");
    out.push(t("pdo.change.mapping", { objects }));
  }
  return out;
}

export interface DraftChange {
  pdo: Pdo;
  changes: string[];
}

/** Every PDO the draft changes against the device, in the draft's order. */
export function draftChanges(device: readonly Pdo[], draft: readonly Pdo[]): DraftChange[] {
  const byKey = new Map(device.map((p) => [pdoKey(p), p]));
  return draft
    .map((pdo) => ({ pdo, changes: pdoChanges(byKey.get(pdoKey(pdo)), pdo) }))
    .filter((c) => c.changes.length > 0);
}

/** The device's PDOs with those of `update` put in their place (a recommendation may name
 * only the PDOs it configures). */
export function mergePdos(base: readonly Pdo[], update: readonly Pdo[]): Pdo[] {
  const byKey = new Map(update.map((p) => [pdoKey(p), p]));
  const merged = base.map((p) => byKey.get(pdoKey(p)) ?? p);
  const known = new Set(base.map(pdoKey));
  return [...merged, ...update.filter((p) => !known.has(pdoKey(p)))];
}

/** RPDOs first, then TPDOs, each by number. */
export function sortPdos(pdos: readonly Pdo[]): Pdo[] {
  return [...pdos].sort((a, b) =>
    a.kind === b.kind ? a.number - b.number : a.kind === "rpdo" ? -1 : 1,
  );
}

export interface ModeChoice {
  code: "pp" | "pv" | "pt" | "hm" | "ip";
  name: string;
  /** Modes of operation (6060h) value. */
  value: number;
}

export const MODES: readonly ModeChoice[] = [
  { code: "pp", name: "Profile position", value: 1 },
  { code: "pv", name: "Profile velocity", value: 3 },
  { code: "pt", name: "Profile torque", value: 4 },
  { code: "hm", name: "Homing", value: 6 },
  { code: "ip", name: "Interpolated position", value: 7 },
];
