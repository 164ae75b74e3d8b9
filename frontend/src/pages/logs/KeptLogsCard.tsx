import { useId, useState, type ReactNode } from "react";

import { DataUsageLine } from "../../components/DataUsage";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { formatBytes, formatDateTime } from "../../lib/format";
import { useAction, useApi } from "../../lib/useApi";
import { useMay } from "../../session/context";
import { deleteLog, keptLogs } from "./logsApi";
import type { KeptLog } from "./types";

interface Props {
  /** The log on show, if any (marked in the list). */
  current: string | null;
  /** Changes when a decode finished: the list is read again. */
  version: number;
  onOpen: (id: string) => void;
  onDeleted: (id: string) => void;
}

/** The decoded logs the server keeps (the oldest go beyond the quota): open one again, or
 * delete it. */
export function KeptLogsCard({ current, version, onOpen, onDeleted }: Props): ReactNode {
  const { t } = useTranslation();
  const id = useId();
  const operate = useMay("operate");
  const logs = useApi((signal) => keptLogs(signal), `kept-logs-${version}`);
  const [asking, setAsking] = useState<KeptLog | null>(null);
  const [deleted, setDeleted] = useState(0);
  const remove = useAction(async (log: KeptLog) => {
    await deleteLog(log.id);
    setAsking(null);
    setDeleted((n) => n + 1);
    logs.reload();
    onDeleted(log.id);
  });
  const list = logs.data;
  return (
    <section className="card" aria-labelledby={`${id}-h`}>
      <header className="card-header">
        <h2 id={`${id}-h`}>{t("logs.page.kept.heading")}</h2>
        {list && (
          <span className="muted small">{t("logs.page.kept.count", { count: list.length })}</span>
        )}
        {logs.loading && <Spinner label={t("logs.page.kept.loading")} />}
      </header>
      <DataUsageLine kind="logs" version={version * 1000 + deleted} />
      <ErrorText error={logs.error} onRetry={logs.reload} />
      {list?.length === 0 && <p className="muted">{t("logs.page.kept.empty")}</p>}
      {list && list.length > 0 && (
        <table className="data-table" aria-label={t("logs.page.kept.heading")}>
          <thead>
            <tr>
              <th>{t("logs.page.kept.log")}</th>
              <th>{t("logs.page.kept.decoded")}</th>
              <th className="num">{t("logs.page.kept.size")}</th>
              <th>{t("logs.page.kept.actions")}</th>
            </tr>
          </thead>
          <tbody>
            {list.map((log) => (
              <tr key={log.id} className={log.id === current ? "selected" : undefined}>
                <td className="mono">{log.name}</td>
                <td>{formatDateTime(log.created)}</td>
                <td className="num">{formatBytes(log.size_bytes)}</td>
                <td className="inline">
                  <button type="button" className="small" onClick={() => onOpen(log.id)}>
                    {t("logs.page.kept.open")}
                  </button>
                  <button
                    type="button"
                    className="small"
                    {...operate.gate(t("logs.page.kept.gateDelete"), { disabled: remove.busy })}
                    onClick={() => setAsking(log)}
                  >
                    {t("logs.page.kept.delete")}
                  </button>
                </td>
              </tr>
            ))}
          </tbody>
        </table>
      )}
      {asking && (
        <Dialog
          title={t("logs.page.kept.confirmTitle", { name: asking.name })}
          onClose={() => setAsking(null)}
          actions={
            <>
              <button type="button" onClick={() => setAsking(null)}>
                {t("logs.page.kept.cancel")}
              </button>
              <button
                type="button"
                className="danger"
                disabled={remove.busy}
                onClick={() => void remove.run(asking)}
              >
                {t("logs.page.kept.confirm", { name: asking.name })}
              </button>
            </>
          }
        >
          <p>
            {t("logs.page.kept.confirmText", {
              name: asking.name,
              size: formatBytes(asking.size_bytes),
              time: formatDateTime(asking.created),
            })}
          </p>
          <ErrorText error={remove.error} />
        </Dialog>
      )}
    </section>
  );
}
