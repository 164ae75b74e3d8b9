import type { ReactNode } from "react";

import type { Permit } from "../../session/permit";
import { changeText, formatDateTime, objectText, resultDetail, resultLabel } from "./auditText";
import type { AuditEntry } from "./types";

/** The user of what the server writes by itself (a jog stopped when its keep-alives stopped). */
const SERVER_USER = "servodesk";

function AuditRow({
  entry,
  fresh,
  configure,
  onUndo,
}: {
  entry: AuditEntry;
  fresh: boolean;
  configure: Permit;
  onUndo: (entry: AuditEntry) => void;
}): ReactNode {
  const detail = resultDetail(entry);
  const classes = [`audit-${entry.result}`, fresh ? "audit-fresh" : ""].filter(Boolean);
  return (
    <tr className={classes.join(" ")} data-testid={`audit-${entry.id}`}>
      <td className="mono small nowrap" title={`Entry ${entry.id}`}>
        {formatDateTime(entry.time)}
      </td>
      <td>
        {entry.user}
        <span className="muted small block">
          {entry.user === SERVER_USER ? "by itself" : entry.role}
        </span>
      </td>
      <td className="small">{entry.client ?? "—"}</td>
      <td className="num">{entry.node ?? "—"}</td>
      <td>
        <span className="badge audit-action">{entry.action}</span>
        <span className="block audit-what">{entry.what}</span>
        {entry.undo_of !== null && (
          <span className="muted small block">undoes entry {entry.undo_of}</span>
        )}
        {entry.undone_by !== null && (
          <span className="muted small block">undone by entry {entry.undone_by}</span>
        )}
      </td>
      <td className="mono nowrap">{objectText(entry)}</td>
      <td className="mono audit-change">{changeText(entry)}</td>
      <td>
        <span className={`badge audit-result result-${entry.result}`}>
          {resultLabel(entry.result)}
        </span>
        {detail && <span className="small block audit-detail">{detail}</span>}
      </td>
      <td>
        {entry.undoable && (
          <button
            type="button"
            className="small"
            aria-label={`Undo entry ${entry.id}`}
            onClick={() => onUndo(entry)}
            {...configure.gate("undo a change", {
              title: `Write ${entry.old === null ? "the old value" : String(entry.old)} back`,
            })}
          >
            Undo
          </button>
        )}
      </td>
    </tr>
  );
}

/** Newest first; failed and pending entries stand out, the one just made is marked. */
export function AuditTable({
  entries,
  freshId,
  configure,
  onUndo,
}: {
  entries: readonly AuditEntry[];
  freshId: number | null;
  configure: Permit;
  onUndo: (entry: AuditEntry) => void;
}): ReactNode {
  return (
    <div className="table-scroll">
      <table className="data-table audit-table">
        <thead>
          <tr>
            <th>Time</th>
            <th>User</th>
            <th>Client</th>
            <th>Node</th>
            <th>Action</th>
            <th>Object</th>
            <th>Old → new</th>
            <th>Result</th>
            <th>
              <span className="visually-hidden">Undo</span>
            </th>
          </tr>
        </thead>
        <tbody>
          {entries.map((entry) => (
            <AuditRow
              key={entry.id}
              entry={entry}
              fresh={entry.id === freshId}
              configure={configure}
              onUndo={onUndo}
            />
          ))}
        </tbody>
      </table>
    </div>
  );
}
