import { useState, type ReactNode } from "react";

import type { DriveState, QuickStopResult } from "../api/drive";
import { driveAction, quickStopAll } from "../api/driveApi";
import { i18n, useTranslation } from "../i18n";
import { useAction } from "../lib/useApi";
import { ErrorText } from "./ErrorText";

/** One click, always enabled, open to every client whoever holds the drive: the drive brakes
 * on its quick-stop ramp (605Ah) and stays in Quick stop active. */
export function QuickStopButton({
  node,
  onStopped,
  compact = false,
}: {
  node: number;
  onStopped?: (state: DriveState) => void;
  compact?: boolean;
}): ReactNode {
  const { t } = useTranslation();
  const stop = useAction(async () => {
    const state = await driveAction(node, "quick-stop");
    onStopped?.(state);
  });
  return (
    <span className="quick-stop-wrap">
      <button
        type="button"
        className={compact ? "quick-stop small" : "quick-stop"}
        aria-label={t("quickStop.nodeLabel", { node })}
        title={t("quickStop.title")}
        onClick={() => void stop.run()}
      >
        {t(compact ? "quickStop.buttonCompact" : "quickStop.button")}
      </button>
      <ErrorText error={stop.error} inline />
    </span>
  );
}

/** "Stopped nodes 1, 3; not reached: node 2 (timeout)". */
export function quickStopSummary(result: QuickStopResult): string {
  const separator = i18n.t("common.listSeparator");
  const failed = Object.entries(result.failed);
  const stopped = result.stopped.length
    ? i18n.t("quickStop.stopped", {
        count: result.stopped.length,
        nodes: result.stopped.join(separator),
      })
    : i18n.t("quickStop.none");
  if (!failed.length) return stopped;
  const notReached = failed
    .map(([node, reason]) => i18n.t("quickStop.failedNode", { node, reason }))
    .join(separator);
  return i18n.t("quickStop.withFailed", { stopped, failed: notReached });
}

/** The Network page's "Quick stop all": every known drive at once. */
export function QuickStopAllButton(): ReactNode {
  const { t } = useTranslation();
  const [result, setResult] = useState<QuickStopResult | null>(null);
  const stop = useAction(async () => {
    setResult(null);
    setResult(await quickStopAll());
  });
  return (
    <span className="quick-stop-wrap">
      <button
        type="button"
        className="quick-stop"
        title={t("quickStop.allTitle")}
        onClick={() => void stop.run()}
      >
        {t("quickStop.all")}
      </button>
      {result && (
        <span
          className={Object.keys(result.failed).length ? "error-text small" : "muted small"}
          role="status"
        >
          {quickStopSummary(result)}
        </span>
      )}
      <ErrorText error={stop.error} inline />
    </span>
  );
}
