// Log results in words, and the paging of decoded events. Pure, table-tested.
import { i18n } from "../../i18n";
import { formatCount } from "../../lib/format";
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
    { label: i18n.t("logs.page.stats.frames"), value: formatCount(stats.frames) },
    { label: i18n.t("logs.page.stats.duration"), value: formatDuration(stats.duration_s) },
  ];
  if (stats.nodes) {
    items.push({
      label: i18n.t("logs.page.stats.nodes"),
      value: stats.nodes.length
        ? stats.nodes.join(i18n.t("common.listSeparator"))
        : i18n.t("logs.page.stats.noNodes"),
    });
  }
  if (stats.bus_load_peak_percent != null) {
    const peak = stats.bus_load_peak_percent.toFixed(1);
    const mean = stats.bus_load_mean_percent;
    items.push({
      label: i18n.t("logs.page.stats.busLoad"),
      value:
        mean == null
          ? i18n.t("logs.page.stats.peak", { peak })
          : i18n.t("logs.page.stats.peakMean", { peak, mean: mean.toFixed(1) }),
    });
  }
  if (stats.bitrate) {
    items.push({
      label: i18n.t("logs.page.stats.bitrate"),
      value: `${stats.bitrate / 1000} kbit/s`,
    });
  }
  if (stats.events != null) {
    items.push({ label: i18n.t("logs.page.stats.events"), value: String(stats.events) });
  }
  if (stats.error_frames) {
    items.push({ label: i18n.t("logs.page.stats.errorFrames"), value: String(stats.error_frames) });
  }
  return items;
}

/** "emcy 3 · sdo-abort 1" from the per-kind counts, largest first; frame/bus-load left out. */
export function countsText(counts: Record<string, number>): string {
  return Object.entries(counts)
    .filter(([kind, n]) => n > 0 && kind !== "frame")
    .sort((a, b) => b[1] - a[1] || a[0].localeCompare(b[0]))
    .map(([kind, n]) => `${kind} ${formatCount(n)}`)
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
  if (!first || !last) return i18n.t("logs.page.events.none");
  const range = { first: formatCount(first.seq + 1), last: formatCount(last.seq + 1) };
  return total == null
    ? i18n.t("logs.page.events.range", range)
    : i18n.t("logs.page.events.rangeOf", { ...range, total: formatCount(total) });
}

/** "Recording BLF: 1,234 frames, 12.000 s (3 dropped)" or "Not recording". */
export function recordingText(info: RecordingInfo, now: number): string {
  if (!info.active) return i18n.t("logs.page.recording.off");
  const duration =
    info.since == null
      ? ""
      : i18n.t("logs.page.recording.duration", {
          duration: formatDuration(Math.max(0, now - info.since)),
        });
  const dropped = info.dropped
    ? i18n.t("logs.page.recording.dropped", { dropped: formatCount(info.dropped) })
    : "";
  return i18n.t("logs.page.recording.on", {
    format: info.format ? ` ${info.format.toUpperCase()}` : "",
    frames: formatCount(info.frames),
    duration,
    dropped,
  });
}
