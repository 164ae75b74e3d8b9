// Small display helpers shared by the pages.
import type { NodeInfo } from "../api/types";
import { currentLanguage, currentLocale, i18n } from "../i18n";

/** 0x0000_02A0-style hex of an identity number; "—" when unknown. */
export function hex(value: number | null | undefined, digits = 8): string {
  if (value == null) return "—";
  return `0x${value.toString(16).toUpperCase().padStart(digits, "0")}`;
}

/** "6041h" / "1018h:02" as the manuals write object addresses. */
export function odAddress(index: number, subindex?: number): string {
  const idx = index.toString(16).toUpperCase().padStart(4, "0");
  if (subindex === undefined) return `${idx}h`;
  return `${idx}h:${subindex.toString(16).toUpperCase().padStart(2, "0")}`;
}

export function formatBitrate(bitrate: number | null | undefined): string {
  if (bitrate == null) return "—";
  if (bitrate >= 1_000_000 && bitrate % 1_000_000 === 0) return `${bitrate / 1_000_000} Mbit/s`;
  if (bitrate >= 1000 && bitrate % 1000 === 0) return `${bitrate / 1000} kbit/s`;
  return `${bitrate} bit/s`;
}

export function formatAge(ms: number | null | undefined): string {
  if (ms == null) return "—";
  if (ms < 1000) return `${ms} ms`;
  if (ms < 60_000) return `${(ms / 1000).toFixed(1)} s`;
  return `${Math.floor(ms / 60_000)} min`;
}

/** Local wall-clock time of a UNIX timestamp (seconds), with milliseconds. */
export function formatClock(unixSeconds: number): string {
  const date = new Date(unixSeconds * 1000);
  const pad = (n: number, w = 2): string => String(n).padStart(w, "0");
  return `${pad(date.getHours())}:${pad(date.getMinutes())}:${pad(date.getSeconds())}.${pad(date.getMilliseconds(), 3)}`;
}

/** A count with the language's digit grouping: "1,234". */
export function formatCount(value: number): string {
  return value.toLocaleString(currentLocale());
}

export function formatValue(value: number | string | null | undefined): string {
  if (value == null) return "—";
  return String(value);
}

/** The last `parts` segments of a path: "cia402/drive.eds" rather than a server's full path. */
export function shortPath(path: string, parts = 2): string {
  const segments = path.split(/[\\/]/).filter(Boolean);
  return segments.slice(-parts).join("/") || path;
}

/** Bytes in binary units: "512 B", "715 KiB", "9.9 MiB", "1.4 GiB". */
export function formatBytes(bytes: number): string {
  if (bytes < 1024) return `${bytes} B`;
  if (bytes < 1024 * 1024) return `${(bytes / 1024).toFixed(0)} KiB`;
  if (bytes < 1024 ** 3) return `${(bytes / (1024 * 1024)).toFixed(1)} MiB`;
  return `${(bytes / 1024 ** 3).toFixed(1)} GiB`;
}

/** Local date and time of an epoch-seconds timestamp: "2026-11-25 09:09:03" (the Faults tab's
 * own, in lib/faultText.ts, adds milliseconds). */
export function formatDateTime(epochS: number): string {
  const date = new Date(epochS * 1000);
  const pad = (n: number): string => String(n).padStart(2, "0");
  return (
    `${date.getFullYear()}-${pad(date.getMonth() + 1)}-${pad(date.getDate())} ` +
    `${pad(date.getHours())}:${pad(date.getMinutes())}:${pad(date.getSeconds())}`
  );
}

/** A CAN identifier as the manuals print it: 0x181. */
export function formatCobId(cobId: number): string {
  return `0x${cobId.toString(16).toUpperCase().padStart(3, "0")}`;
}

/** One decimal below 10, none from 10 on (9.96 reads "10", not "10.0"). */
function tenthsBelowTen(value: number): string {
  const tenths = Math.round(value * 10) / 10;
  return tenths < 10 ? tenths.toFixed(1) : tenths.toFixed(0);
}

/** A bus load: "4.2 %", "37 %". */
export function formatPercent(value: number): string {
  return `${tenthsBelowTen(value)} %`;
}

/** A frame rate: "—" unknown, "0/s", "2.5/s", "500/s". */
export function formatRate(value: number | null | undefined): string {
  if (value == null) return "—";
  if (value === 0) return "0/s";
  return `${tenthsBelowTen(value)}/s`;
}

/** The label of a profile ServoDesk ships, in the page's language (by its key); in English, or
 * for a profile the page does not know (a user's), as the server labels it. */
export function profileLabel(info: Pick<NodeInfo, "profile" | "profile_label">): string {
  const label = info.profile_label;
  if (!info.profile || currentLanguage() === "en") return label;
  const key = `format.profile.${info.profile}`;
  return i18n.t(key, { defaultValue: label });
}

/** "1 · MDi-S1-C · DVS_CANOPEN": id, profile, the drive's own name (1008h). */
export function nodeTitle(node: number, info: NodeInfo | undefined): string {
  if (!info) return i18n.t("format.unknownNode", { node });
  return [String(node), profileLabel(info), info.name].filter(Boolean).join(" · ");
}
