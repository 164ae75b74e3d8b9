import type { ReactNode } from "react";

import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
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
  const undo = useAction(async (force: boolean) => {
    onUndone(await undoEntry(entry.id, force));
  });
  // someone changed the value since: writing the old one back anyway is a separate decision
  const changed = undo.error?.kind === "changed_since";
  return (
    <Dialog
      title={`Undo entry ${entry.id}`}
      onClose={onClose}
      actions={
        <>
          <button type="button" onClick={onClose}>
            Cancel
          </button>
          <button
            type="button"
            className="primary"
            disabled={undo.busy}
            onClick={() => void undo.run(changed)}
          >
            {changed ? "Write it back anyway" : `Write ${valueText(entry.old)} back`}
          </button>
        </>
      }
    >
      <p>{entry.what}</p>
      <p>
        <strong>{undoText(entry)}</strong>
      </p>
      <p className="muted small">The undo is logged as an entry of its own.</p>
      <ErrorText error={undo.error} />
    </Dialog>
  );
}
