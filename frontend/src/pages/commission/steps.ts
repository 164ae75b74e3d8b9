// What the page knows about the nine steps: which the server runs, which move the axis, where
// a manual one is done, and how figures and evidence read (pure functions, table-tested).
// The page's own words come from the catalogue; the server's texts (reasons,
// evidence values) stay as sent.
import { currentLanguage, currentLocale, i18n, type MessageKey } from "../../i18n";
import type { CommissioningRecord, CommissioningStep, StepKey } from "./types";

export const STEP_KEYS: readonly StepKey[] = [
  "identity",
  "communication",
  "parameters",
  "pdo",
  "limits",
  "stop_test",
  "test_move",
  "homing",
  "store_verify",
];

/** Steps with an automated part (`run`): all nine. */
export const AUTOMATED: ReadonlySet<StepKey> = new Set<StepKey>(STEP_KEYS);

/** Steps whose run moves the axis. */
export const MOVING: ReadonlySet<StepKey> = new Set<StepKey>(["stop_test", "test_move", "homing"]);

/** Where a step can also be done by hand (then signed off here): the node tab and its label. */
export const MANUAL_PAGE: Partial<Record<StepKey, { tab: string; label: MessageKey }>> = {
  pdo: { tab: "pdos", label: "commission.manual.pdo" },
  homing: { tab: "drive", label: "commission.manual.homing" },
};

/** Run defaults, as the server's (docs/api.md): stop test 200 rpm, test move 0.5 rev. */
export const DEFAULT_SPEED_RPM = 200;
export const DEFAULT_DISTANCE_REV = 0.5;
export const MAX_DISTANCE_REV = 100;

/** While it runs: what the user waits for. */
export const RUNNING_TEXT: Partial<Record<StepKey, MessageKey>> = {
  stop_test: "commission.runningText.stop_test",
  test_move: "commission.runningText.test_move",
  pdo: "commission.runningText.pdo",
  homing: "commission.runningText.homing",
  store_verify: "commission.runningText.store_verify",
};

/** The steps' titles in the page's language. */
const STEP_TITLES: Record<StepKey, MessageKey> = {
  identity: "commission.stepTitle.identity",
  communication: "commission.stepTitle.communication",
  parameters: "commission.stepTitle.parameters",
  pdo: "commission.stepTitle.pdo",
  limits: "commission.stepTitle.limits",
  stop_test: "commission.stepTitle.stop_test",
  test_move: "commission.stepTitle.test_move",
  homing: "commission.stepTitle.homing",
  store_verify: "commission.stepTitle.store_verify",
};

/** A step's title: in English the server's own (the record keeps it), in another language the
 * catalogue's for the step's key. */
export function stepTitle(step: Pick<CommissioningStep, "key" | "title">): string {
  return currentLanguage() === "en" ? step.title : i18n.t(STEP_TITLES[step.key]);
}

/** A step's (server-sent, English) title inside a sentence: lower case in English ("run
 * homing"), as sent in languages without case. */
export function titleInSentence(title: string): string {
  return currentLanguage() === "en" ? title.toLowerCase() : title;
}

/** A UNIX time as local date and time: the browser's own format in English (as the page always
 * printed it), the chosen language's otherwise. */
export function localDateTime(unixSeconds: number): string {
  const date = new Date(unixSeconds * 1000);
  return currentLanguage() === "en" ? date.toLocaleString() : date.toLocaleString(currentLocale());
}

/** A UNIX time as local time of day, like localDateTime. */
export function localTime(unixSeconds: number): string {
  const date = new Date(unixSeconds * 1000);
  return currentLanguage() === "en"
    ? date.toLocaleTimeString()
    : date.toLocaleTimeString(currentLocale());
}

/** The steps in the flow's order (the server's list is already in it; unknown keys last). */
export function orderedSteps(record: CommissioningRecord): CommissioningStep[] {
  const rank = (key: string): number => {
    const at = STEP_KEYS.indexOf(key as StepKey);
    return at < 0 ? STEP_KEYS.length : at;
  };
  return [...record.steps].sort((a, b) => rank(a.key) - rank(b.key));
}

/** "3 of 9 steps closed": done or skipped. */
export function progress(record: CommissioningRecord): { closed: number; total: number } {
  const closed = record.steps.filter((s) => s.status === "done" || s.status === "skipped").length;
  return { closed, total: record.steps.length };
}

/** A figure's unit from its name's ending (stop_time_s → s, distance_rev → rev, …). */
export function figureUnit(name: string): string {
  if (name.endsWith("_rpm")) return "rpm";
  if (name.endsWith("_rev")) return "rev";
  if (name.endsWith("_pct")) return "%";
  if (name.endsWith("_ms")) return "ms";
  if (name.endsWith("_s")) return "s";
  if (name.endsWith("_ratio")) return "×";
  return "";
}

/** A figure's name in words: "quick_stop_stop_time_s" → "quick stop stop time". */
export function figureLabel(name: string): string {
  return name
    .replace(/_(rpm|rev|pct|ms|s)$/, "")
    .replace(/_/g, " ")
    .trim();
}

export function formatNumber(value: number): string {
  if (Number.isInteger(value)) return String(value);
  const abs = Math.abs(value);
  const digits = abs >= 100 ? 1 : abs >= 1 ? 3 : 4;
  return String(Number(value.toFixed(digits)));
}

export interface FigureRow {
  name: string;
  label: string;
  value: string;
  unit: string;
}

export function figureRows(figures: Record<string, number> | undefined): FigureRow[] {
  return Object.entries(figures ?? {}).map(([name, value]) => ({
    name,
    label: figureLabel(name),
    value: formatNumber(value),
    unit: figureUnit(name),
  }));
}

/** Objects the manuals print in hex: 1000h (device type), 1018h (identity), 1016h/1017h
 * (consumer entries hold node id and time in one word), 6502h (supported modes). */
const HEX_INDICES: ReadonlySet<number> = new Set([0x1000, 0x1016, 0x1018, 0x6502]);

/** A read value as the manuals print it: hex for the objects above, else the server's text. */
export function valueText(entry: { index?: unknown; value?: unknown; text?: unknown }): string {
  if (
    typeof entry.index === "number" &&
    HEX_INDICES.has(entry.index) &&
    typeof entry.value === "number" &&
    Number.isInteger(entry.value) &&
    entry.value >= 0
  ) {
    return `0x${entry.value.toString(16).toUpperCase().padStart(8, "0")}`;
  }
  if (typeof entry.value === "number") return formatNumber(entry.value);
  if (typeof entry.text === "string" && entry.text !== "") return entry.text;
  return plain(entry.value);
}

/** Any evidence value as one line of text; `key` names it (`at`, `…_at`: a UNIX time). */
export function plain(value: unknown, key = ""): string {
  if (value === null || value === undefined) return "—";
  if ((key === "at" || key.endsWith("_at")) && typeof value === "number" && value > 1e9) {
    return localTime(value);
  }
  if (typeof value === "number") return formatNumber(value);
  if (typeof value === "boolean") {
    return value ? i18n.t("commission.evidence.yes") : i18n.t("commission.evidence.no");
  }
  if (typeof value === "string") return value;
  if (Array.isArray(value)) return value.map((v) => plain(v)).join(", ") || "—";
  if (isRecordLike(value)) {
    const parts = Object.entries(value).map(([k, v]) => `${k}: ${plain(v, k)}`);
    return parts.join(", ") || "—";
  }
  return JSON.stringify(value);
}

export function isRecordLike(value: unknown): value is Record<string, unknown> {
  return typeof value === "object" && value !== null && !Array.isArray(value);
}

/** Rows of an evidence list (`values`, `entries`, `lost`, …): only the objects in it. */
export function rowsOf(value: unknown): Record<string, unknown>[] {
  return Array.isArray(value) ? value.filter(isRecordLike) : [];
}

/** The values store_verify found lost over the reset, in words: "2006:08 PA-103: expected 5000, now 6000". */
export function lostLines(step: CommissioningStep): string[] {
  return rowsOf(step.evidence?.lost).map((row) =>
    i18n.t("commission.step.lostLine", {
      what: `${plain(row.object)}${row.name ? ` ${plain(row.name)}` : ""}`,
      expected: plain(row.expected),
      now: plain(row.now),
    }),
  );
}

/** "by local, 27/11/2026, 12:03" style line; empty for a step nobody touched. */
export function whoWhen(step: CommissioningStep): string {
  const at = step.at ? localDateTime(step.at) : "";
  if (!step.by) return at;
  return at
    ? i18n.t("commission.step.byAt", { who: step.by, at })
    : i18n.t("commission.step.by", { who: step.by });
}
