import { useState, type ReactNode } from "react";

import type { CompareResult } from "../../api/types";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import type { ApiError } from "../../api/errors";
import { useTranslation } from "../../i18n";
import { odAddress } from "../../lib/format";

interface Props {
  node: number;
  filename: string;
  /** The node compared with the file, read just now. */
  preview: CompareResult;
  busy: boolean;
  error: ApiError | null;
  onWrite: (confirmIdentity: boolean) => void;
  onClose: () => void;
}

/** What loading a DCF would change, shown before anything is written. A file made for
 * another kind of device is named as such and needs one more, explicit agreement. */
export function LoadDcfDialog({
  node,
  filename,
  preview,
  busy,
  error,
  onWrite,
  onClose,
}: Props): ReactNode {
  const { t } = useTranslation();
  const [otherDevice, setOtherDevice] = useState(false);
  const changes = preview.rows.filter((row) => row.differs_from_file);
  const identity = preview.identity;
  // another device, a file that names none, a heartbeat the bus should not carry: each asked
  const questions = preview.confirm ?? [];
  const otherKind = identity?.checked !== false && identity?.matches === false;
  const mismatch = questions.length > 0;
  const count = changes.length;
  return (
    <Dialog
      title={t("params.load.title", { filename, node })}
      onClose={onClose}
      actions={
        <>
          <button type="button" onClick={onClose}>
            {t("params.cancel")}
          </button>
          <button
            type="button"
            className={mismatch ? "primary danger" : "primary"}
            disabled={busy || (mismatch && !otherDevice)}
            onClick={() => onWrite(mismatch)}
          >
            {count === 0 ? t("params.load.writeAnyway") : t("params.load.writeValues", { count })}
          </button>
          {busy && <Spinner label={t("params.load.writing")} />}
        </>
      }
    >
      {mismatch && (
        <div className="warning" role="alert">
          {questions.map((question) => (
            <p key={question}>
              {question === identity?.message ? (
                <>
                  <strong>
                    {otherKind ? t("params.load.otherDevice") : t("params.load.unchecked")}
                  </strong>{" "}
                  {t("params.load.otherMeaning", { question, node })}
                </>
              ) : (
                <>
                  <strong>{t("params.load.checkFirst")}</strong>{" "}
                  {t("params.load.question", { question })}
                </>
              )}
            </p>
          ))}
          <label className="check">
            <input
              type="checkbox"
              checked={otherDevice}
              onChange={(e) => setOtherDevice(e.target.checked)}
            />
            {t("params.load.writeToNode", { node })}
          </label>
        </div>
      )}
      <p>
        {count === 0
          ? t("params.load.nothing", { node, filename })
          : t("params.load.wouldChange", { count, node })}
      </p>
      {count > 0 && (
        <div className="table-scroll compare-scroll">
          <table className="data-table" aria-label={t("params.load.table")}>
            <thead>
              <tr>
                <th scope="col">{t("params.load.name")}</th>
                <th scope="col">{t("params.load.index")}</th>
                <th scope="col">{t("params.load.deviceNow")}</th>
                <th scope="col">{t("params.load.fromFile")}</th>
                <th scope="col">{t("params.load.unit")}</th>
              </tr>
            </thead>
            <tbody>
              {changes.map((row) => (
                <tr key={`${row.index}:${row.subindex}`}>
                  <td>{row.name}</td>
                  <td className="mono">{odAddress(row.index, row.subindex)}</td>
                  <td className="mono">{row.device_text || "—"}</td>
                  <td className="mono cell-differs">{row.file_text || "—"}</td>
                  <td>{row.unit || "—"}</td>
                </tr>
              ))}
            </tbody>
          </table>
        </div>
      )}
      <ErrorText error={error} />
    </Dialog>
  );
}
