// The cursors' logic, pure: two cursors A and B on a finished capture (s from its trigger),
// moved by pointer on the overview, by keys and by number inputs; and the readout as rows.
import { i18n } from "../../i18n";
import type { Measurement } from "./types";

export type CursorName = "a" | "b";

export interface Cursors {
  a: number;
  b: number;
}

export interface Span {
  start: number;
  end: number;
}

/** Where the cursors start on a capture: at a quarter and three quarters of it. */
export function initialCursors(span: Span): Cursors {
  const length = span.end - span.start;
  return { a: span.start + length / 4, b: span.start + (3 * length) / 4 };
}

export function clampTime(t: number, span: Span): number {
  return Math.min(span.end, Math.max(span.start, t));
}

/** A pixel across the overview's `width` as a time of the span (clamped to it). */
export function timeAt(x: number, width: number, span: Span): number {
  if (width <= 0) return span.start;
  return clampTime(span.start + (x / width) * (span.end - span.start), span);
}

export function xAt(t: number, width: number, span: Span): number {
  const length = span.end - span.start;
  return length > 0 ? ((clampTime(t, span) - span.start) / length) * width : 0;
}

/** The cursor a pointer at time `t` takes: the nearer one (A on a tie). */
export function nearestCursor(cursors: Cursors, t: number): CursorName {
  return Math.abs(cursors.b - t) < Math.abs(cursors.a - t) ? "b" : "a";
}

/** A keyboard step: a 1-2-5 round number near 1/200 of the span (1 ms on a 0.3 s capture). */
export function stepOf(span: Span): number {
  const raw = (span.end - span.start) / 200;
  if (!(raw > 0)) return 0.001;
  const decade = 10 ** Math.floor(Math.log10(raw));
  const mantissa = raw / decade;
  return (mantissa < 1.5 ? 1 : mantissa < 3.5 ? 2 : 5) * decade;
}

/** The cursor after a key: ←/→ one step (Shift: ten), Home/End the span's ends. null: not a
 * key the cursor takes (so the page keeps it). */
export function nudge(
  t: number,
  key: string,
  shift: boolean,
  span: Span,
  step = stepOf(span),
): number | null {
  const by = shift ? step * 10 : step;
  switch (key) {
    case "ArrowLeft":
    case "ArrowDown":
      return clampTime(t - by, span);
    case "ArrowRight":
    case "ArrowUp":
      return clampTime(t + by, span);
    case "PageDown":
      return clampTime(t - step * 10, span);
    case "PageUp":
      return clampTime(t + step * 10, span);
    case "Home":
      return span.start;
    case "End":
      return span.end;
    default:
      return null;
  }
}

/** A typed cursor time: the number, or why not (what to type instead). */
export function parseCursor(text: string, span: Span): number | string {
  const value = Number(text.trim().replace(",", "."));
  if (text.trim() === "" || !Number.isFinite(value)) return i18n.t("scope.cursorInput.typeTime");
  if (value < span.start || value > span.end) {
    return i18n.t("scope.cursorInput.range", {
      start: formatNumber(span.start),
      end: formatNumber(span.end),
    });
  }
  return value;
}

/** A value with up to 6 significant digits ("—" where there is none). */
export function formatNumber(value: number | null | undefined): string {
  if (value == null || !Number.isFinite(value)) return "—";
  if (value === 0) return "0";
  const text =
    Math.abs(value) >= 1e6 || Math.abs(value) < 1e-4
      ? value.toExponential(4)
      : String(Number(value.toPrecision(6)));
  return text;
}

/** A time difference as people read it: "250 ms", "1.5 s", "-20 ms", "800 µs". */
export function formatDuration(seconds: number): string {
  const size = Math.abs(seconds);
  if (size === 0) return "0 s";
  if (size < 1e-3) return `${formatNumber(seconds * 1e6)} µs`;
  if (size < 1) return `${formatNumber(seconds * 1e3)} ms`;
  return `${formatNumber(seconds)} s`;
}

export interface ReadoutRow {
  key: string;
  signal: string;
  unit: string;
  a: string;
  b: string;
  delta: string;
  min: string;
  max: string;
  mean: string;
  count: string;
}

/** Bit-field words (controlword 6040h, statusword 6041h): read in hex as the manuals print
 * them; a difference or mean of two bit patterns means nothing. */
const BIT_WORDS = new Set([0x6040, 0x6041]);

/** 0x0250 for a bit-field word's value. */
export function formatWord(value: number | null | undefined): string {
  if (value === null || value === undefined || !Number.isFinite(value)) return "—";
  return `0x${Math.round(value).toString(16).toUpperCase().padStart(4, "0")}`;
}

/** One row per signal, every number formatted for the table. */
export function readoutRows(measurement: Measurement): ReadoutRow[] {
  return measurement.signals.map((s) => {
    const word = BIT_WORDS.has(s.index);
    const value = word ? formatWord : formatNumber;
    return {
      key: `${s.node}:${s.index}:${s.subindex}`,
      signal: `node ${s.node} ${s.name}`,
      unit: s.unit,
      a: value(s.at_a),
      b: value(s.at_b),
      delta: word ? "—" : formatNumber(s.delta),
      min: value(s.min),
      max: value(s.max),
      mean: word ? "—" : formatNumber(s.mean),
      count: String(s.count),
    };
  });
}
