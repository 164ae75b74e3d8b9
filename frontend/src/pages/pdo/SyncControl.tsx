import { useState, type ReactNode } from "react";

import { api, call } from "../../api/client";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useAction, useApi } from "../../lib/useApi";
import { useMay } from "../../session/context";

/** For a synchronous mapping: whether SYNC is produced, and a way to start it (`onStarted`
 * then, e.g. to check a draft again). */
export function SyncControl({ onStarted }: { onStarted?: () => void } = {}): ReactNode {
  const sync = useApi((signal) => call(api.GET("/api/sync", { signal })), "sync");
  const [periodMs, setPeriodMs] = useState("10");
  const configure = useMay("configure");
  const produce = useAction(async () => {
    const answer = await call(
      api.PUT("/api/sync", {
        body: { producing: true, period_us: Math.round(Number(periodMs) * 1000) },
      }),
    );
    sync.setData(() => answer);
    onStarted?.();
  });
  const period = Number(periodMs);
  const periodOk = periodMs.trim() !== "" && period > 0 && period <= 60_000;

  if (sync.data?.producing) {
    return (
      <span className="inline pdo-sync small" role="status">
        SYNC produced every {(sync.data.period_us ?? 0) / 1000} ms
      </span>
    );
  }
  return (
    <span className="inline pdo-sync">
      <span className="small">The mapping is synchronous and SYNC is off:</span>
      <label className="small" htmlFor="pdo-sync-ms">
        every
      </label>
      <input
        id="pdo-sync-ms"
        className="tiny"
        inputMode="decimal"
        aria-invalid={!periodOk}
        value={periodMs}
        onChange={(e) => setPeriodMs(e.target.value)}
      />
      <span className="small">ms</span>
      <button
        type="button"
        onClick={() => void produce.run()}
        {...configure.gate("start SYNC", {
          disabled: !periodOk || produce.busy || sync.loading,
        })}
      >
        Produce SYNC
      </button>
      {produce.busy && <Spinner label="Starting SYNC" />}
      <ErrorText error={produce.error ?? sync.error} inline />
    </span>
  );
}
