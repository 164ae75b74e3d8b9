import { useEffect, type ReactNode } from "react";

import { api, call } from "../api/client";
import type { components } from "../api/schema";
import { formatBytes } from "../lib/format";
import { useApi } from "../lib/useApi";

export type Usage = components["schemas"]["DataUsage"];
/** What a page keeps: its own quota is shown; none: the whole data directory. */
export type UsageKind = "logs" | "captures";

const NEARLY = 0.9; // of a quota: say so before the oldest start to go

/** Words for what the data directory holds (pure, table-tested). `warn`: the user should act
 * (the quota is nearly used up, or the disk is nearly full and captures would end). */
export function usageWords(data: Usage, kind?: UsageKind): { text: string; warn: boolean } {
  const free = `${formatBytes(data.free_bytes)} free on the disk`;
  const lowDisk = data.free_bytes < 2 * data.min_free_bytes;
  const diskNote = lowDisk
    ? `; below ${formatBytes(data.min_free_bytes)} free, captures end to leave room for the audit log`
    : "";
  if (kind === undefined) {
    const parts = [
      `decoded logs ${formatBytes(data.logs_bytes)}`,
      `captures ${formatBytes(data.captures_bytes)}`,
      `recordings ${formatBytes(data.recordings_bytes)}`,
    ].join(", ");
    return {
      text: `Data directory: ${formatBytes(data.total_bytes)} (${parts}) · ${free}${diskNote}`,
      warn: lowDisk,
    };
  }
  const [label, used, keep] =
    kind === "logs"
      ? ["Decoded logs", data.logs_bytes, data.logs_keep_bytes]
      : ["Captures", data.captures_bytes, data.captures_keep_bytes];
  return {
    text:
      `${label} take ${formatBytes(used)} of the ${formatBytes(keep)} kept; ` +
      `beyond that the oldest are deleted · ${free}${diskNote}`,
    warn: used >= NEARLY * keep || lowDisk,
  };
}

/** One line on what the data directory holds (GET /api/health); read again when `version`
 * changes (a file kept or deleted) and every `pollMs`. */
export function DataUsageLine({
  kind,
  version = 0,
  pollMs = 30_000,
}: {
  kind?: UsageKind;
  version?: number;
  pollMs?: number;
}): ReactNode {
  const health = useApi((signal) => call(api.GET("/api/health", { signal })), `usage-${version}`);
  const { reload } = health;
  useEffect(() => {
    const timer = setInterval(reload, pollMs);
    return () => clearInterval(timer);
  }, [reload, pollMs]);
  const data = health.data?.data;
  if (!data) return null;
  const words = usageWords(data, kind);
  return (
    <p
      className={words.warn ? "small data-usage busy" : "small muted data-usage"}
      data-testid="data-usage"
    >
      {words.text}
    </p>
  );
}
