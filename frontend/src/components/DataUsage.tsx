import { useEffect, type ReactNode } from "react";

import { api, call } from "../api/client";
import type { components } from "../api/schema";
import { i18n, useTranslation } from "../i18n";
import { formatBytes } from "../lib/format";
import { useApi } from "../lib/useApi";

export type Usage = components["schemas"]["DataUsage"];
/** What a page keeps: its own quota is shown; none: the whole data directory. */
export type UsageKind = "logs" | "captures";

const NEARLY = 0.9; // of a quota: say so before the oldest start to go

/** Words for what the data directory holds (pure, table-tested). `warn`: the user should act
 * (the quota is nearly used up, or the disk is nearly full and captures would end). */
export function usageWords(data: Usage, kind?: UsageKind): { text: string; warn: boolean } {
  const free = i18n.t("usage.free", { size: formatBytes(data.free_bytes) });
  const lowDisk = data.free_bytes < 2 * data.min_free_bytes;
  const diskNote = lowDisk
    ? i18n.t("usage.lowDisk", { size: formatBytes(data.min_free_bytes) })
    : "";
  if (kind === undefined) {
    const parts = i18n.t("usage.parts", {
      logs: formatBytes(data.logs_bytes),
      captures: formatBytes(data.captures_bytes),
      recordings: formatBytes(data.recordings_bytes),
    });
    return {
      text: i18n.t("usage.total", {
        total: formatBytes(data.total_bytes),
        parts,
        free,
        lowDisk: diskNote,
      }),
      warn: lowDisk,
    };
  }
  const [used, keep] =
    kind === "logs"
      ? [data.logs_bytes, data.logs_keep_bytes]
      : [data.captures_bytes, data.captures_keep_bytes];
  const values = { used: formatBytes(used), keep: formatBytes(keep), free, lowDisk: diskNote };
  return {
    text: kind === "logs" ? i18n.t("usage.logs", values) : i18n.t("usage.captures", values),
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
  useTranslation(); // the words are built below: re-render on a language switch
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
