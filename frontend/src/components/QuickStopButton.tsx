import { useState, type ReactNode } from "react";

import type { DriveState, QuickStopResult } from "../api/drive";
import { driveAction, quickStopAll } from "../api/driveApi";
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
  const stop = useAction(async () => {
    const state = await driveAction(node, "quick-stop");
    onStopped?.(state);
  });
  return (
    <span className="quick-stop-wrap">
      <button
        type="button"
        className={compact ? "quick-stop small" : "quick-stop"}
        aria-label={`Quick stop node ${node}`}
        title="Quick stop (controlword 0002h): brake on the quick-stop ramp now"
        onClick={() => void stop.run()}
      >
        {compact ? "Quick stop" : "■ Quick stop"}
      </button>
      <ErrorText error={stop.error} inline />
    </span>
  );
}

/** "Stopped nodes 1, 3; not reached: node 2 (timeout)". */
export function quickStopSummary(result: QuickStopResult): string {
  const failed = Object.entries(result.failed);
  const stopped = result.stopped.length
    ? `Stopped node${result.stopped.length === 1 ? "" : "s"} ${result.stopped.join(", ")}`
    : "No drive to stop";
  if (!failed.length) return stopped;
  return `${stopped}; not reached: ${failed.map(([n, why]) => `node ${n} (${why})`).join(", ")}`;
}

/** The Network page's "Quick stop all": every known drive at once. */
export function QuickStopAllButton(): ReactNode {
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
        title="Quick stop every drive on the bus"
        onClick={() => void stop.run()}
      >
        ■ Quick stop all
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
