// Small display helpers shared by the pages.

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
