import { useState, type ReactNode } from "react";

import { api, call } from "../../api/client";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { useAction, useApi } from "../../lib/useApi";
import { useMay } from "../../session/context";

/** For a synchronous mapping: whether SYNC is produced, and a way to start it (`onStarted`
 * then, e.g. to check a draft again). */
export function SyncControl({ onStarted }: { onStarted?: () => void } = {}): ReactNode {
  const { t } = useTranslation();
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
        {t("pdo.sync.produced", { ms: (sync.data.period_us ?? 0) / 1000 })}
      </span>
    );
  }
  return (
    <span className="inline pdo-sync">
      <span className="small">{t("pdo.sync.off")}</span>
      <label className="small" htmlFor="pdo-sync-ms">
        {t("pdo.sync.every")}
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
        {...configure.gate(t("pdo.sync.gate"), {
          disabled: !periodOk || produce.busy || sync.loading,
        })}
      >
        {t("pdo.sync.produce")}
      </button>
      {produce.busy && <Spinner label={t("pdo.sync.starting")} />}
      <ErrorText error={produce.error ?? sync.error} inline />
    </span>
  );
}
