import { useId, useState, type ReactNode } from "react";

import { DataUsageLine } from "../../components/DataUsage";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
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
        <h2 id={`${id}-h`}>Decoded logs</h2>
        {list && <span className="muted small">{list.length} kept</span>}
        {logs.loading && <Spinner label="Loading the decoded logs" />}
      </header>
      <DataUsageLine kind="logs" version={version * 1000 + deleted} />
      <ErrorText error={logs.error} onRetry={logs.reload} />
      {list?.length === 0 && <p className="muted">No decoded logs kept.</p>}
      {list && list.length > 0 && (
        <table className="data-table" aria-label="Decoded logs">
          <thead>
            <tr>
              <th>Log</th>
              <th>Decoded</th>
              <th className="num">Size</th>
              <th>Open · delete</th>
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
                    Open
                  </button>
                  <button
                    type="button"
                    className="small"
                    {...operate.gate("delete a decoded log", { disabled: remove.busy })}
                    onClick={() => setAsking(log)}
                  >
                    Delete
                  </button>
                </td>
              </tr>
            ))}
          </tbody>
        </table>
      )}
      {asking && (
        <Dialog
          title={`Delete ${asking.name}?`}
          onClose={() => setAsking(null)}
          actions={
            <>
              <button type="button" onClick={() => setAsking(null)}>
                Cancel
              </button>
              <button
                type="button"
                className="danger"
                disabled={remove.busy}
                onClick={() => void remove.run(asking)}
              >
                Delete {asking.name}
              </button>
            </>
          }
        >
          <p>
            The decoded events of {asking.name} ({formatBytes(asking.size_bytes)}, decoded{" "}
            {formatDateTime(asking.created)}) are deleted from the server. Decode the file again to
            see them; exports already downloaded stay.
          </p>
          <ErrorText error={remove.error} />
        </Dialog>
      )}
    </section>
  );
}
