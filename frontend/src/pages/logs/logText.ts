// Log results in words, and the paging of decoded events. Pure, table-tested.
import type { LogEvent, LogStats, RecordingInfo } from "./types";

const num = (value: unknown): number | null =>
  typeof value === "number" && Number.isFinite(value) ? value : null;

/** The free-form `stats` of a decoded log, checked field by field. */
export function parseStats(raw: Record<string, unknown>): LogStats {
  const counts: Record<string, number> = {};
  if (typeof raw.counts === "object" && raw.counts !== null) {
    for (const [kind, n] of Object.entries(raw.counts)) {
      if (typeof n === "number") counts[kind] = n;
    }
  }
  const nodes = Array.isArray(raw.nodes)
    ? raw.nodes.filter((n): n is number => typeof n === "number")
    : null;
  return {
    frames: num(raw.frames) ?? 0,
    duration_s: num(raw.duration_s) ?? 0,
    nodes,
    counts,
    error_frames: num(raw.error_frames) ?? 0,
    bitrate: num(raw.bitrate),
    bus_load_peak_percent: num(raw.bus_load_peak_percent),
    bus_load_mean_percent: num(raw.bus_load_mean_percent),
    events: num(raw.events),
  };
}

/** A log time: wall-clock "12:03:44.120" for absolute stamps, "+12.345 s" for stamps relative
 * to the start of a recording (ASC and TRC files often start at 0). */
export function logClock(t: number): string {
  if (t < 1e8) return `+${t.toFixed(3)} s`;
  const date = new Date(t * 1000);
  const pad = (n: number, w = 2): string => String(n).padStart(w, "0");
  return `${pad(date.getHours())}:${pad(date.getMinutes())}:${pad(date.getSeconds())}.${pad(date.getMilliseconds(), 3)}`;
}

/** "1.234 s", "2 min 5.0 s", "1 h 2 min". */
export function formatDuration(seconds: number): string {
  if (!Number.isFinite(seconds) || seconds < 0) return "—";
  if (seconds < 60) return `${seconds.toFixed(3)} s`;
  const minutes = Math.floor(seconds / 60);
  if (minutes < 60) return `${minutes} min ${(seconds - minutes * 60).toFixed(1)} s`;
  return `${Math.floor(minutes / 60)} h ${minutes % 60} min`;
}

export interface StatItem {
  label: string;
  value: string;
}

/** The log's totals as label/value pairs, in the order the page shows them. */
export function statItems(stats: LogStats): StatItem[] {
  const items: StatItem[] = [
    { label: "Frames", value: stats.frames.toLocaleString("en-US") },
    { label: "Duration", value: formatDuration(stats.duration_s) },
  ];
  if (stats.nodes) {
    items.push({ label: "Node ids", value: stats.nodes.length ? stats.nodes.join(", ") : "none" });
  }
  if (stats.bus_load_peak_percent != null) {
    const mean = stats.bus_load_mean_percent;
    items.push({
      label: "Bus load",
      value: `peak ${stats.bus_load_peak_percent.toFixed(1)} %${mean == null ? "" : `, mean ${mean.toFixed(1)} %`}`,
    });
  }
  if (stats.bitrate) items.push({ label: "Bitrate", value: `${stats.bitrate / 1000} kbit/s` });
  if (stats.events != null) items.push({ label: "Events", value: String(stats.events) });
  if (stats.error_frames) items.push({ label: "Error frames", value: String(stats.error_frames) });
  return items;
}

/** "emcy 3 · sdo-abort 1" from the per-kind counts, largest first; frame/bus-load left out. */
export function countsText(counts: Record<string, number>): string {
  return Object.entries(counts)
    .filter(([kind, n]) => n > 0 && kind !== "frame")
    .sort((a, b) => b[1] - a[1] || a[0].localeCompare(b[0]))
    .map(([kind, n]) => `${kind} ${n.toLocaleString("en-US")}`)
    .join(" · ");
}

/** Forward paging over seq-ordered events: the cursors of the pages seen, for "previous". */
export interface Pager {
  /** `since` of each page shown so far; the last one is the current page. */
  starts: number[];
}

export const FIRST_PAGE: Pager = { starts: [0] };

export function currentStart(pager: Pager): number {
  return pager.starts[pager.starts.length - 1] ?? 0;
}

export function pageForward(pager: Pager, start: number): Pager {
  return { starts: [...pager.starts, start] };
}

export function pageBack(pager: Pager): Pager {
  return pager.starts.length > 1 ? { starts: pager.starts.slice(0, -1) } : pager;
}

/** "Events 501–1,000 of 1,234" (seq counts from 0). */
export function pageLabel(page: readonly LogEvent[], total: number | null): string {
  const first = page[0];
  const last = page[page.length - 1];
  if (!first || !last) return "No events";
  const n = (v: number): string => v.toLocaleString("en-US");
  const of = total == null ? "" : ` of ${n(total)}`;
  return `Events ${n(first.seq + 1)}–${n(last.seq + 1)}${of}`;
}

/** "Recording BLF: 1,234 frames, 12.000 s (3 dropped)" or "Not recording". */
export function recordingText(info: RecordingInfo, now: number): string {
  if (!info.active) return "Not recording";
  const format = info.format ? ` ${info.format.toUpperCase()}` : "";
  const duration = info.since == null ? "" : `, ${formatDuration(Math.max(0, now - info.since))}`;
  const dropped = info.dropped ? ` (${info.dropped.toLocaleString("en-US")} dropped)` : "";
  return `Recording${format}: ${info.frames.toLocaleString("en-US")} frames${duration}${dropped}`;
}
