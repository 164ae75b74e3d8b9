// The Scope page's form and what is shown from the API's answers, as pure functions: the
// capture request built from what the user typed (with the reason when it cannot be sent), a
// signal's source in words, a trigger in words, values with their units.
import type { OdEntry, OdObject } from "../../api/types";
import { currentLocale, i18n, type MessageKey } from "../../i18n";
import { formatBytes, formatCobId, formatDateTime, odAddress } from "../../lib/format";
import { filterOd, parseOdQuery } from "../../lib/odFilter";
import type {
  Capture,
  CaptureRequest,
  CaptureSignal,
  Edge,
  ScopePlan,
  TriggerKind,
  TriggerMode,
  TriggerRequest,
} from "./types";

export { formatBytes, formatDateTime }; // the capture list's sizes and times, for its callers

export const MAX_SIGNALS = 32;
export const MIN_SYNC_PERIOD_US = 500;
export const MAX_SYNC_PERIOD_US = 1_000_000;
export const MAX_DURATION_S = 3600;
export const STATUSWORD = 0x6041;

/** A signal the user picked: an object of one node. */
export interface SignalChoice {
  node: number;
  index: number;
  subindex: number;
  /** The object's name in the node's dictionary (shown in the list). */
  name: string;
}

/** The objects a scope is usually pointed at (CiA 402), one click each. */
export const QUICK_PICKS: readonly { index: number; label: MessageKey; name: string }[] = [
  { index: 0x6064, label: "scope.signals.quick.position", name: "Position actual value" },
  { index: 0x606c, label: "scope.signals.quick.velocity", name: "Velocity actual value" },
  { index: 0x6077, label: "scope.signals.quick.torque", name: "Torque actual value" },
  {
    index: 0x60f4,
    label: "scope.signals.quick.followingError",
    name: "Following error actual value",
  },
  { index: STATUSWORD, label: "scope.signals.quick.statusword", name: "Statusword" },
  { index: 0x60fd, label: "scope.signals.quick.digitalInputs", name: "Digital inputs" },
];

/** The CiA 402 states a state trigger can wait for (as the server names them). */
export const CIA402_STATES: readonly string[] = [
  "not ready to switch on",
  "switch on disabled",
  "ready to switch on",
  "switched on",
  "operation enabled",
  "quick stop active",
  "fault reaction active",
  "fault",
];

/** The trigger section as typed: numbers stay text until the request is built. */
export interface TriggerForm {
  kind: TriggerKind;
  /** level, bit, state: the node watched; emcy: the node sending (null: any node). */
  node: number | null;
  /** level: the watched signal, "node:index:subindex" of a chosen signal. */
  signal: string;
  /** bit: the object whose bit is watched, "index:subindex"; "" for 6041h Statusword. */
  bitObject: string;
  level: string;
  edge: Edge;
  bit: string;
  /** state: the CiA 402 state waited for; "" for any change. */
  state: string;
  preS: string;
  mode: TriggerMode;
  keep: string;
}

export interface ScopeForm {
  signals: SignalChoice[];
  syncPeriodUs: string;
  durationS: string;
  name: string;
  trigger: TriggerForm;
}

export const DEFAULT_TRIGGER: TriggerForm = {
  kind: "none",
  node: null,
  signal: "",
  bitObject: "",
  level: "",
  edge: "rising",
  bit: "",
  state: "",
  preS: "0",
  mode: "single",
  keep: "10",
};

export const DEFAULT_FORM: ScopeForm = {
  signals: [],
  syncPeriodUs: "1000",
  durationS: "5",
  name: "",
  trigger: DEFAULT_TRIGGER,
};

export function signalKey(signal: { node: number; index: number; subindex: number }): string {
  return `${signal.node}:${signal.index}:${signal.subindex}`;
}

/** Add a signal unless it is already chosen or the list is full. */
export function addSignal(signals: readonly SignalChoice[], added: SignalChoice): SignalChoice[] {
  const key = signalKey(added);
  if (signals.length >= MAX_SIGNALS || signals.some((s) => signalKey(s) === key)) {
    return [...signals];
  }
  return [...signals, added];
}

/** "1.5", " 1,5 " → 1.5; "", "abc", "1e999" → null. */
export function parseNumber(text: string): number | null {
  const cleaned = text.trim().replace(",", ".");
  if (cleaned === "") return null;
  const value = Number(cleaned);
  return Number.isFinite(value) ? value : null;
}

function parseInteger(text: string): number | null {
  const value = parseNumber(text);
  return value !== null && Number.isInteger(value) ? value : null;
}

export type BuiltRequest = { ok: true; request: CaptureRequest } | { ok: false; problem: string };

const refuse = (problem: string): BuiltRequest => ({ ok: false, problem });

/** The trigger's part of the request, or why it cannot be built. */
function buildTrigger(
  form: TriggerForm,
  durationS: number,
): { trigger: TriggerRequest } | { problem: string } {
  const pre = parseNumber(form.preS === "" ? "0" : form.preS);
  if (pre === null || pre < 0) return { problem: i18n.t("scope.problem.preNegative") };
  const keep = parseInteger(form.keep);
  if (form.mode === "normal" && (keep === null || keep < 1 || keep > 100)) {
    return { problem: i18n.t("scope.problem.keep") };
  }
  const trigger: TriggerRequest = {
    kind: form.kind,
    edge: form.edge,
    pre_s: form.kind === "none" ? 0 : pre,
    mode: form.mode,
    keep: form.mode === "normal" && keep !== null ? keep : 10,
  };
  if (form.kind !== "none" && pre >= durationS) {
    return { problem: i18n.t("scope.problem.preTooLong") };
  }
  switch (form.kind) {
    case "none":
      return { trigger };
    case "level": {
      const [node, index, subindex] = form.signal.split(":").map(Number);
      if (node === undefined || index === undefined || subindex === undefined || !form.signal) {
        return { problem: i18n.t("scope.problem.levelSignal") };
      }
      const level = parseNumber(form.level);
      if (level === null) return { problem: i18n.t("scope.problem.levelValue") };
      return { trigger: { ...trigger, node, index, subindex, level } };
    }
    case "bit": {
      if (form.node === null) return { problem: i18n.t("scope.problem.bitNode") };
      const bit = parseInteger(form.bit);
      if (bit === null || bit < 0 || bit > 63) return { problem: i18n.t("scope.problem.bitRange") };
      const [index, subindex] = form.bitObject ? form.bitObject.split(":").map(Number) : [];
      return {
        trigger: {
          ...trigger,
          node: form.node,
          bit,
          index: index ?? null,
          subindex: subindex ?? null,
        },
      };
    }
    case "emcy":
      return { trigger: { ...trigger, node: form.node } };
    case "state":
      if (form.node === null) return { problem: i18n.t("scope.problem.stateNode") };
      return { trigger: { ...trigger, node: form.node, state: form.state || null } };
  }
}

/** The request the form describes, or the first thing that keeps it from being sent. */
export function buildRequest(form: ScopeForm): BuiltRequest {
  if (form.signals.length === 0) return refuse(i18n.t("scope.problem.noSignal"));
  if (form.signals.length > MAX_SIGNALS)
    return refuse(i18n.t("scope.problem.tooMany", { max: MAX_SIGNALS }));
  const sync = parseInteger(form.syncPeriodUs);
  if (sync === null || sync < MIN_SYNC_PERIOD_US || sync > MAX_SYNC_PERIOD_US) {
    return refuse(
      i18n.t("scope.problem.sync", {
        min: MIN_SYNC_PERIOD_US,
        max: MAX_SYNC_PERIOD_US.toLocaleString(currentLocale()),
      }),
    );
  }
  const duration = parseNumber(form.durationS);
  if (duration === null || duration <= 0 || duration > MAX_DURATION_S) {
    return refuse(i18n.t("scope.problem.duration", { max: MAX_DURATION_S }));
  }
  const name = form.name.trim();
  if (name.length > 80) return refuse(i18n.t("scope.problem.name"));
  const built = buildTrigger(form.trigger, duration);
  if ("problem" in built) return refuse(built.problem);
  return {
    ok: true,
    request: {
      signals: form.signals.map(({ node, index, subindex }) => ({ node, index, subindex })),
      sync_period_us: sync,
      duration_s: duration,
      trigger: built.trigger,
      name: name || null,
      start_nodes: true,
    },
  };
}

/** The plan's source column: "TPDO2 · 0x281" or "SDO polling". */
export function sourceText(signal: Pick<CaptureSignal, "source" | "tpdo" | "cob_id">): string {
  if (signal.source === "sdo") return i18n.t("scope.source.sdo");
  const tpdo = signal.tpdo == null ? "TPDO" : `TPDO${signal.tpdo}`;
  return signal.cob_id == null ? tpdo : `${tpdo} · COB-ID ${formatCobId(signal.cob_id)}`;
}

/** "node 1 · 6064h:00" */
export function signalAddress(signal: { node: number; index: number; subindex: number }): string {
  return `node ${signal.node} · ${odAddress(signal.index, signal.subindex)}`;
}

const BIT_PATTERNS = new Set(["statusword", "controlword", "digital_inputs"]);

/** A reading with its unit: bit patterns in hex ("0x0237"), others to about 5 digits. */
export function formatReading(
  value: number | null | undefined,
  signal: Pick<CaptureSignal, "unit" | "quantity" | "bits">,
): string {
  if (value == null) return "—";
  if (BIT_PATTERNS.has(signal.quantity) && Number.isInteger(value) && value >= 0) {
    const digits = Math.max(4, Math.ceil((signal.bits || 16) / 4));
    return `0x${value.toString(16).toUpperCase().padStart(digits, "0")}`;
  }
  const text = shortNumber(value);
  return signal.unit ? `${text} ${signal.unit}` : text;
}

/** Up to 5 significant digits, whole numbers from 10 000 up, an exponent only for the
 * extremes: 12.346, 120, 0.000123, 123,457. */
export function shortNumber(value: number): string {
  const magnitude = Math.abs(value);
  if (value !== 0 && (magnitude >= 1e12 || magnitude < 1e-4)) return value.toExponential(3);
  if (magnitude >= 1e4) return value.toLocaleString(currentLocale(), { maximumFractionDigits: 0 });
  return value.toLocaleString(currentLocale(), { maximumSignificantDigits: 5 });
}

const EDGES: Record<Edge, MessageKey> = {
  rising: "scope.triggerText.edge.rising",
  falling: "scope.triggerText.edge.falling",
  either: "scope.triggerText.edge.either",
};

/** A trigger in words: "free-running", "node 1 6064h:00 crosses 1000 (rising)". */
export function triggerText(trigger: TriggerRequest): string {
  let text: string;
  switch (trigger.kind) {
    case "none":
      return i18n.t("scope.triggerText.none");
    case "level":
      text = i18n.t("scope.triggerText.level", {
        node: trigger.node ?? "?",
        address: odAddress(trigger.index ?? 0, trigger.subindex ?? 0),
        level: trigger.level ?? "?",
        edge: i18n.t(EDGES[trigger.edge]),
      });
      break;
    case "bit":
      text = i18n.t("scope.triggerText.bit", {
        node: trigger.node ?? "?",
        address: odAddress(trigger.index ?? STATUSWORD, trigger.subindex ?? 0),
        bit: trigger.bit ?? "?",
        edge: i18n.t(EDGES[trigger.edge]),
      });
      break;
    case "emcy":
      text =
        trigger.node == null
          ? i18n.t("scope.triggerText.emcyAny")
          : i18n.t("scope.triggerText.emcyNode", { node: trigger.node });
      break;
    case "state":
      text = trigger.state
        ? i18n.t("scope.triggerText.stateEnters", {
            node: trigger.node ?? "?",
            state: trigger.state,
          })
        : i18n.t("scope.triggerText.stateChanges", { node: trigger.node ?? "?" });
      break;
  }
  if (trigger.pre_s > 0) text = i18n.t("scope.triggerText.pre", { text, pre: trigger.pre_s });
  if (trigger.mode === "normal") {
    text = i18n.t("scope.triggerText.rearmed", { text, keep: trigger.keep });
  }
  return text;
}

export function isActive(capture: Pick<Capture, "state"> | null | undefined): boolean {
  const state = capture?.state;
  return state === "arming" || state === "armed" || state === "running";
}

/** The watched signal's raw level in its physical unit, as a hint beside the level field. */
export function levelHint(
  level: string,
  signal: Pick<CaptureSignal, "scale" | "unit" | "raw_unit"> | undefined,
): string | null {
  if (!signal) return null;
  const raw = signal.raw_unit
    ? i18n.t("scope.levelHint.rawIn", { unit: signal.raw_unit })
    : i18n.t("scope.levelHint.raw");
  const value = parseNumber(level);
  if (value === null || signal.scale === 1 || !signal.unit) return raw;
  return i18n.t("scope.levelHint.scaled", {
    raw,
    value: shortNumber(value * signal.scale),
    unit: signal.unit,
  });
}

/** An object of a node's dictionary the picker lists. */
export interface PickableEntry {
  index: number;
  subindex: number;
  /** "Statusword"; a record's entry as "Encoder resolution · Motor revolutions". */
  name: string;
  unit: string;
  pdoMappable: boolean;
}

function readable(entry: OdEntry): boolean {
  return entry.access !== "wo";
}

/** The readable entries of the dictionary that match the search box (OD page syntax: 6041,
 * 0x1018, 1018:2 or words of a name), at most `limit`, and how many matched in all. */
export function findEntries(
  objects: readonly OdObject[],
  query: string,
  limit = 40,
): { entries: PickableEntry[]; total: number } {
  const entries: PickableEntry[] = [];
  let total = 0;
  for (const { object, subs } of filterOd(objects, parseOdQuery(query))) {
    for (const sub of subs) {
      if (!readable(sub)) continue;
      if (object.subs.length > 1 && sub.subindex === 0) continue; // "number of entries"
      total += 1;
      if (entries.length >= limit) continue;
      const name =
        object.subs.length > 1 && sub.name !== object.name
          ? `${object.name} · ${sub.name}`
          : sub.name;
      entries.push({
        index: sub.index,
        subindex: sub.subindex,
        name,
        unit: sub.unit,
        pdoMappable: sub.pdo_mappable,
      });
    }
  }
  return { entries, total };
}

/** The dictionary's entry at index:subindex, if it has one. */
export function findEntry(
  objects: readonly OdObject[] | undefined,
  index: number,
  subindex = 0,
): OdEntry | undefined {
  return objects?.find((o) => o.index === index)?.subs.find((s) => s.subindex === subindex);
}

/** A capture's state as one word (the capture list's badge too). */
export const STATE_WORD: Record<Capture["state"], MessageKey> = {
  arming: "scope.list.states.arming",
  armed: "scope.list.states.armed",
  running: "scope.list.states.running",
  done: "scope.list.states.done",
  failed: "scope.list.states.failed",
};

/** Why Start is disabled, in words; null when the capture may start. */
export function startReason(
  built: BuiltRequest,
  plan: { plan: ScopePlan | null; error: unknown; checking: boolean },
  current: Pick<Capture, "id" | "state"> | null,
): string | null {
  if (current && isActive(current)) {
    return i18n.t("scope.reason.active", {
      id: current.id,
      state: i18n.t(STATE_WORD[current.state]),
    });
  }
  if (!built.ok) return built.problem;
  if (plan.checking) return i18n.t("scope.reason.checking");
  if (plan.error) return i18n.t("scope.reason.failed");
  if (!plan.plan) return i18n.t("scope.reason.notChecked");
  if (!plan.plan.ok) return plan.plan.problems[0] ?? i18n.t("scope.reason.impossible");
  return null;
}
