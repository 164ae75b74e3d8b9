import { useState, type ReactNode } from "react";

import type { CompareResult } from "../../api/types";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import type { ApiError } from "../../api/errors";
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
      title={`Load ${filename} onto node ${node}`}
      onClose={onClose}
      actions={
        <>
          <button type="button" onClick={onClose}>
            Cancel
          </button>
          <button
            type="button"
            className={mismatch ? "primary danger" : "primary"}
            disabled={busy || (mismatch && !otherDevice)}
            onClick={() => onWrite(mismatch)}
          >
            {count === 0 ? "Write the set anyway" : `Write ${count} value${count === 1 ? "" : "s"}`}
          </button>
          {busy && <Spinner label="Writing the parameter set" />}
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
                    {otherKind
                      ? "This file is for another device."
                      : "This file cannot be checked against the node."}
                  </strong>{" "}
                  {question}. Its values may mean something else on node {node}.
                </>
              ) : (
                <>
                  <strong>Check before writing:</strong> {question}.
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
            Write it to node {node} anyway
          </label>
        </div>
      )}
      <p>
        {count === 0
          ? `Node ${node} already has every value of ${filename}: nothing would change.`
          : `${count} value${count === 1 ? "" : "s"} on node ${node} would change. Nothing has been written yet.`}
      </p>
      {count > 0 && (
        <div className="table-scroll compare-scroll">
          <table className="data-table" aria-label="Values that would change">
            <thead>
              <tr>
                <th scope="col">Name</th>
                <th scope="col">Index</th>
                <th scope="col">Device now</th>
                <th scope="col">From the file</th>
                <th scope="col">Unit</th>
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
