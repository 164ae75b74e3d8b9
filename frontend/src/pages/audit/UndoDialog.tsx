import type { ReactNode } from "react";

import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { useTranslation } from "../../i18n";
import { useAction } from "../../lib/useApi";
import { undoEntry } from "./auditApi";
import { undoText, valueText } from "./auditText";
import type { AuditEntry } from "./types";

/** Names the object and the value it writes back before it does. */
export function UndoDialog({
  entry,
  onClose,
  onUndone,
}: {
  entry: AuditEntry;
  onClose: () => void;
  onUndone: (undo: AuditEntry) => void;
}): ReactNode {
  const { t } = useTranslation();
  const undo = useAction(async (force: boolean) => {
    onUndone(await undoEntry(entry.id, force));
  });
  // someone changed the value since: writing the old one back anyway is a separate decision
  const changed = undo.error?.kind === "changed_since";
  return (
    <Dialog
      title={t("logs.audit.undo.title", { id: entry.id })}
      onClose={onClose}
      actions={
        <>
          <button type="button" onClick={onClose}>
            {t("logs.audit.undo.cancel")}
          </button>
          <button
            type="button"
            className="primary"
            disabled={undo.busy}
            onClick={() => void undo.run(changed)}
          >
            {changed
              ? t("logs.audit.undo.anyway")
              : t("logs.audit.undo.writeBack", { value: valueText(entry.old) })}
          </button>
        </>
      }
    >
      <p>{entry.what}</p>
      <p>
        <strong>{undoText(entry)}</strong>
      </p>
      <p className="muted small">{t("logs.audit.undo.logged")}</p>
      <ErrorText error={undo.error} />
    </Dialog>
  );
}
