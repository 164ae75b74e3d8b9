// The live readouts' sparklines: the last values polled from the capture (~4 per second),
// kept per signal, drawn as one SVG path. Pure.
import { signalKey } from "./model";
import type { Capture } from "./types";

export const HISTORY = 100;

/** Last values per signal ("node:index:subindex" → oldest first), for one capture. */
export interface History {
  capture: number;
  values: Readonly<Record<string, readonly number[]>>;
}

export const EMPTY_HISTORY: History = { capture: -1, values: {} };

/** The history with each signal's latest value appended (at most `limit` kept). A capture
 * other than the history's starts a new one. */
export function pushHistory(history: History, capture: Capture, limit = HISTORY): History {
  const old = history.capture === capture.id ? history.values : {};
  const values: Record<string, readonly number[]> = {};
  for (const signal of capture.signals) {
    const key = signalKey(signal);
    const kept = old[key] ?? [];
    const value = signal.last_value;
    if (value == null || !Number.isFinite(value)) {
      values[key] = kept;
      continue;
    }
    const next = [...kept, value];
    values[key] = next.length > limit ? next.slice(next.length - limit) : next;
  }
  return { capture: capture.id, values };
}

function round(value: number): string {
  return String(Math.round(value * 10) / 10);
}

/** An SVG path through `values` spread over `width`, scaled into `height` (minus `pad` at top
 * and bottom). A flat series is drawn through the middle; fewer than two values draw nothing
 * but a dot-like stub. `capacity`: how many values the full width holds (the newest sits at
 * the right edge), so the line grows from the right as values come in. */
export function sparklinePath(
  values: readonly number[],
  width: number,
  height: number,
  { pad = 2, capacity = values.length }: { pad?: number; capacity?: number } = {},
): string {
  if (values.length === 0) return "";
  const slots = Math.max(capacity, values.length, 2) - 1;
  const step = width / slots;
  const start = width - (values.length - 1) * step;
  let low = Infinity;
  let high = -Infinity;
  for (const value of values) {
    low = Math.min(low, value);
    high = Math.max(high, value);
  }
  const span = high - low;
  const inner = height - 2 * pad;
  const y = (value: number): number =>
    span === 0 ? height / 2 : pad + inner - ((value - low) / span) * inner;
  if (values.length === 1) {
    const first = values[0] ?? 0;
    return `M${round(width - 1)},${round(y(first))}H${round(width)}`;
  }
  return values
    .map((value, i) => `${i === 0 ? "M" : "L"}${round(start + i * step)},${round(y(value))}`)
    .join("");
}

/** The overview of a whole signal: its min/max bins (`times`, `low`, `high`) as one filled
 * band over `width` × `height`, time mapped from [start, end]. A flat signal is drawn through
 * the middle; a single bin as a thin band. */
export function envelopePath(
  trace: {
    times: readonly number[];
    low: readonly number[];
    high: readonly number[];
  },
  span: { start: number; end: number },
  width: number,
  height: number,
  pad = 4,
): string {
  const n = Math.min(trace.times.length, trace.low.length, trace.high.length);
  if (n === 0) return "";
  let lowest = Infinity;
  let highest = -Infinity;
  for (let i = 0; i < n; i++) {
    lowest = Math.min(lowest, trace.low[i] ?? 0);
    highest = Math.max(highest, trace.high[i] ?? 0);
  }
  const range = highest - lowest;
  const inner = height - 2 * pad;
  const y = (value: number): number =>
    range === 0 ? height / 2 : pad + inner - ((value - lowest) / range) * inner;
  const duration = span.end - span.start;
  const x = (t: number): number => (duration > 0 ? ((t - span.start) / duration) * width : 0);
  const top: string[] = [];
  const bottom: string[] = [];
  for (let i = 0; i < n; i++) {
    const left = x(trace.times[i] ?? 0);
    const next = i + 1 < n ? x(trace.times[i + 1] ?? 0) : width;
    const right = Math.max(left + 0.5, next); // each bin holds until the next: a step signal
    top.push(
      `${round(left)},${round(y(trace.high[i] ?? 0))}L${round(right)},${round(y(trace.high[i] ?? 0))}`,
    );
    bottom.unshift(
      `${round(right)},${round(y(trace.low[i] ?? 0) + 0.5)}L${round(left)},${round(y(trace.low[i] ?? 0) + 0.5)}`,
    );
  }
  return `M${top.join("L")}L${bottom.join("L")}Z`;
}
