import { useState, type ReactNode } from "react";

import type { ApiError } from "../../api/errors";
import { clearDeviceHistory, deviceHistory } from "../../api/faultsApi";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { i18n, useTranslation } from "../../i18n";
import { errorRegisterText, faultCode, faultName, hasNoObject } from "../../lib/faultText";
import { serverText } from "../../lib/serverText";
import { useAction, useApi } from "../../lib/useApi";
import { useMay } from "../../session/context";
import type { DeviceHistoryEntry } from "./types";

function HistoryTable({ entries }: { entries: readonly DeviceHistoryEntry[] }): ReactNode {
  const { t } = useTranslation();
  return (
    <div className="table-scroll">
      <table className="data-table fault-table">
        <caption className="visually-hidden">{t("faults.device.caption")}</caption>
        <thead>
          <tr>
            <th scope="col">1003h</th>
            <th scope="col">{t("faults.device.entry")}</th>
            <th scope="col">{t("faults.device.code")}</th>
            <th scope="col">{t("faults.device.meaning")}</th>
            <th scope="col">{t("faults.device.errorRegister")}</th>
          </tr>
        </thead>
        <tbody>
          {entries.map(({ number, value_hex, fault }) => (
            <tr key={number}>
              <td className="num">
                :{String(number).padStart(2, "0")}
                {number === 1 && <span className="muted small">{t("faults.device.newest")}</span>}
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
    return <p className="muted">{i18n.t("faults.device.noHistory", { node })}</p>;
  }
  return <ErrorText error={error} />;
}

/** The drive's own error history 1003h, decoded; cleared only after the user confirms. */
export function DeviceHistoryCard({ node }: { node: number }): ReactNode {
  const { t } = useTranslation();
  const history = useApi((signal) => deviceHistory(node, signal), `device-history-${node}`);
  const [asking, setAsking] = useState(false);
  const [message, setMessage] = useState<string | null>(null);
  const configure = useMay("configure");
  const clear = useAction(async () => {
    const answer = await clearDeviceHistory(node);
    setMessage(serverText(answer));
    setAsking(false);
    history.reload();
  });
  const data = history.data;
  const entries = data?.entries ?? [];
  const supported = data?.supported ?? true;
  return (
    <section className="card" aria-labelledby="device-history-heading">
      <header className="card-header">
        <h2 id="device-history-heading">{t("faults.device.heading")}</h2>
        {data && supported && (
          <span className="muted small">{t("faults.device.count", { count: data.count })}</span>
        )}
        <span className="spacer" />
        <button type="button" disabled={history.loading} onClick={history.reload}>
          {t("faults.device.read")}
        </button>
        {data && supported && (
          <button
            type="button"
            className="danger"
            {...configure.gate(t("faults.device.gateClear"), {
              disabled: entries.length === 0 || clear.busy,
            })}
            onClick={() => {
              clear.clearError();
              setMessage(null);
              setAsking(true);
            }}
          >
            {t("faults.device.clear")}
          </button>
        )}
        {history.loading && <Spinner label={t("faults.device.reading")} />}
      </header>
      {message && (
        <p className="note" role="status">
          {message}
        </p>
      )}
      {readError(node, history.error)}
      {data?.note && <p className="muted small">{data.note}</p>}
      {data && !supported && <p className="muted">{t("faults.device.noHistory", { node })}</p>}
      {data &&
        supported &&
        (entries.length === 0 ? (
          <p className="muted">{t("faults.device.empty")}</p>
        ) : (
          <HistoryTable entries={entries} />
        ))}
      {asking && (
        <Dialog
          title={t("faults.device.confirmTitle", { node })}
          onClose={() => setAsking(false)}
          actions={
            <>
              <button type="button" onClick={() => setAsking(false)}>
                {t("faults.device.cancel")}
              </button>
              <button
                type="button"
                className="primary"
                disabled={clear.busy}
                onClick={() => void clear.run()}
              >
                {t("faults.device.confirm")}
              </button>
              {clear.busy && <Spinner />}
            </>
          }
        >
          <p>{t("faults.device.confirmText", { count: entries.length })}</p>
          <ErrorText error={clear.error} />
        </Dialog>
      )}
    </section>
  );
}
