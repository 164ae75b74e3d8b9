import { useState, type ReactNode } from "react";

import type { ApiError } from "../../api/errors";
import { clearDeviceHistory, deviceHistory } from "../../api/faultsApi";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { errorRegisterText, faultCode, faultName, hasNoObject } from "../../lib/faultText";
import { useAction, useApi } from "../../lib/useApi";
import { useMay } from "../../session/context";
import type { DeviceHistoryEntry } from "./types";

function HistoryTable({ entries }: { entries: readonly DeviceHistoryEntry[] }): ReactNode {
  return (
    <div className="table-scroll">
      <table className="data-table fault-table">
        <caption className="visually-hidden">Drive&apos;s error history</caption>
        <thead>
          <tr>
            <th scope="col">1003h</th>
            <th scope="col">Entry</th>
            <th scope="col">Code</th>
            <th scope="col">Meaning</th>
            <th scope="col">Error register</th>
          </tr>
        </thead>
        <tbody>
          {entries.map(({ number, value_hex, fault }) => (
            <tr key={number}>
              <td className="num">
                :{String(number).padStart(2, "0")}
                {number === 1 && <span className="muted small"> newest</span>}
              </td>
              <td className="mono">{value_hex}</td>
              <td className="mono">{faultCode(fault)}</td>
              <td>{faultName(fault)}</td>
              <td className="small">{errorRegisterText(fault.error_register)}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}

/** The read failed because the drive has no 1003h: that is an answer, not an error. */
function readError(node: number, error: ApiError | null): ReactNode {
  if (!error) return null;
  if (hasNoObject(error.abortCode)) {
    return <p className="muted">Node {node} keeps no error history of its own (no 1003h).</p>;
  }
  return <ErrorText error={error} />;
}

/** The drive's own error history 1003h, decoded; cleared only after the user confirms. */
export function DeviceHistoryCard({ node }: { node: number }): ReactNode {
  const history = useApi((signal) => deviceHistory(node, signal), `device-history-${node}`);
  const [asking, setAsking] = useState(false);
  const [message, setMessage] = useState<string | null>(null);
  const configure = useMay("configure");
  const clear = useAction(async () => {
    const answer = await clearDeviceHistory(node);
    setMessage(answer.message);
    setAsking(false);
    history.reload();
  });
  const data = history.data;
  const entries = data?.entries ?? [];
  const supported = data?.supported ?? true;
  return (
    <section className="card" aria-labelledby="device-history-heading">
      <header className="card-header">
        <h2 id="device-history-heading">Drive&apos;s error history 1003h</h2>
        {data && supported && <span className="muted small">{data.count} stored</span>}
        <span className="spacer" />
        <button type="button" disabled={history.loading} onClick={history.reload}>
          Read 1003h
        </button>
        {data && supported && (
          <button
            type="button"
            className="danger"
            {...configure.gate("clear the error history", {
              disabled: entries.length === 0 || clear.busy,
            })}
            onClick={() => {
              clear.clearError();
              setMessage(null);
              setAsking(true);
            }}
          >
            Clear history…
          </button>
        )}
        {history.loading && <Spinner label="Reading 1003h" />}
      </header>
      {message && (
        <p className="note" role="status">
          {message}
        </p>
      )}
      {readError(node, history.error)}
      {data?.note && <p className="muted small">{data.note}</p>}
      {data && !supported && (
        <p className="muted">Node {node} keeps no error history of its own (no 1003h).</p>
      )}
      {data &&
        supported &&
        (entries.length === 0 ? (
          <p className="muted">The drive&apos;s history is empty.</p>
        ) : (
          <HistoryTable entries={entries} />
        ))}
      {asking && (
        <Dialog
          title={`Clear node ${node}'s error history?`}
          onClose={() => setAsking(false)}
          actions={
            <>
              <button type="button" onClick={() => setAsking(false)}>
                Cancel
              </button>
              <button
                type="button"
                className="primary"
                disabled={clear.busy}
                onClick={() => void clear.run()}
              >
                Clear 1003h
              </button>
              {clear.busy && <Spinner />}
            </>
          }
        >
          <p>
            Writes 0 to 1003h:00: the drive forgets its {entries.length} stored error
            {entries.length === 1 ? "" : "s"}. This cannot be undone; ServoDesk&apos;s own fault
            history stays.
          </p>
          <ErrorText error={clear.error} />
        </Dialog>
      )}
    </section>
  );
}
