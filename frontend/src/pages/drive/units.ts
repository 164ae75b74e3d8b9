// Number formatting for the drive's values: fixed decimals per unit, a real minus sign, "—"
// for what the drive does not report. Units and decimals stay as engineers write them in any
// language (zh-CN uses the same digits and decimal point).
import { i18n, type MessageKey } from "../../i18n";

function fixed(value: number, decimals: number): string {
  const text = value.toFixed(decimals);
  // "-0.00" reads as motion where there is none
  const zero = Number(text) === 0;
  return (zero ? text.replace(/^-/, "") : text).replace(/^-/, "−");
}

export function formatRev(value: number | null | undefined): string {
  return value == null ? "—" : `${fixed(value, 3)} rev`;
}

export function formatInc(value: number | null | undefined): string {
  if (value == null) return "—";
  return `${fixed(value, 0).replace(/\B(?=(\d{3})+(?!\d))/g, "\u202f")} inc`;
}

export function formatRpm(value: number | null | undefined): string {
  return value == null ? "—" : `${fixed(value, 1)} rpm`;
}

export function formatPct(value: number | null | undefined): string {
  return value == null ? "—" : `${fixed(value, 1)} %`;
}

export function formatMs(value: number | null | undefined, decimals = 2): string {
  return value == null ? "—" : `${fixed(value, decimals)} ms`;
}

/** A field the user types: a finite number, or null (empty or not a number). */
export function parseNumber(text: string): number | null {
  const trimmed = text
    .trim()
    .replace(/\u2212/g, "-")
    .replace(",", ".");
  if (trimmed === "") return null;
  const value = Number(trimmed);
  return Number.isFinite(value) ? value : null;
}

/** A typed number within [min, max] (either bound optional), with the reason when not. */
export function checkRange(
  text: string,
  { min, max, positive = false }: { min?: number | null; max?: number | null; positive?: boolean },
): { value: number | null; error: string | null } {
  const value = parseNumber(text);
  if (value === null) return { value: null, error: i18n.t("drive.check.enterNumber") };
  if (positive && value <= 0) return { value: null, error: i18n.t("drive.check.aboveZero") };
  if (min != null && value < min)
    return { value: null, error: i18n.t("drive.check.atLeast", { min }) };
  if (max != null && value > max)
    return { value: null, error: i18n.t("drive.check.atMost", { max }) };
  return { value, error: null };
}

/** Mode short names as engineers say them. */
export const MODE_LABELS: Readonly<Record<string, MessageKey>> = {
  pp: "drive.mode.pp",
  vl: "drive.mode.vl",
  pv: "drive.mode.pv",
  pt: "drive.mode.pt",
  hm: "drive.mode.hm",
  ip: "drive.mode.ip",
  csp: "drive.mode.csp",
  csv: "drive.mode.csv",
  cst: "drive.mode.cst",
};

export function modeLabel(mode: string | null | undefined): string {
  if (mode == null || mode === "") return i18n.t("drive.mode.none");
  const key = MODE_LABELS[mode];
  return key ? i18n.t(key) : mode;
}
