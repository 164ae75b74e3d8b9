import type { ReactNode } from "react";

import { useTranslation } from "../../i18n";
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
  const { t } = useTranslation();
  const detail = resultDetail(entry);
  const classes = [`audit-${entry.result}`, fresh ? "audit-fresh" : ""].filter(Boolean);
  return (
    <tr className={classes.join(" ")} data-testid={`audit-${entry.id}`}>
      <td className="mono small nowrap" title={t("logs.audit.table.entry", { id: entry.id })}>
        {formatDateTime(entry.time)}
      </td>
      <td>
        {entry.user}
        <span className="muted small block">
          {entry.user === SERVER_USER ? t("logs.audit.table.byItself") : entry.role}
        </span>
      </td>
      <td className="small">{entry.client ?? "—"}</td>
      <td className="num">{entry.node ?? "—"}</td>
      <td>
        <span className="badge audit-action">{entry.action}</span>
        <span className="block audit-what">{entry.what}</span>
        {entry.undo_of !== null && (
          <span className="muted small block">
            {t("logs.audit.table.undoes", { id: entry.undo_of })}
          </span>
        )}
        {entry.undone_by !== null && (
          <span className="muted small block">
            {t("logs.audit.table.undoneBy", { id: entry.undone_by })}
          </span>
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
            aria-label={t("logs.audit.table.undoLabel", { id: entry.id })}
            onClick={() => onUndo(entry)}
            {...configure.gate(t("logs.audit.table.gateUndo"), {
              title:
                entry.old === null
                  ? t("logs.audit.table.writeOldBack")
                  : t("logs.audit.table.writeBack", { value: String(entry.old) }),
            })}
          >
            {t("logs.audit.table.undo")}
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
  const { t } = useTranslation();
  return (
    <div className="table-scroll">
      <table className="data-table audit-table">
        <thead>
          <tr>
            <th>{t("logs.audit.table.time")}</th>
            <th>{t("logs.audit.table.user")}</th>
            <th>{t("logs.audit.table.client")}</th>
            <th>{t("logs.audit.table.node")}</th>
            <th>{t("logs.audit.table.action")}</th>
            <th>{t("logs.audit.table.object")}</th>
            <th>{t("logs.audit.table.change")}</th>
            <th>{t("logs.audit.table.result")}</th>
            <th>
              <span className="visually-hidden">{t("logs.audit.table.undo")}</span>
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
