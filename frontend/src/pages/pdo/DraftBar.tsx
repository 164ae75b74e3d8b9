import { useState, type ReactNode } from "react";

import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useAction } from "../../lib/useApi";
import { draftChanges, isSynchronous, pdoLabel } from "./model";
import { applyPdos, validatePdos, type ApplyOutcome } from "./pdoApi";
import { SyncControl } from "./SyncControl";
import type { Pdo, Validation } from "./types";

interface Props {
  node: number;
  device: readonly Pdo[];
  draft: Pdo[];
  source: string;
  validation: Validation | null;
  onValidated: (validation: Validation) => void;
  onOutcome: (outcome: ApplyOutcome) => void;
  onDiscard: () => void;
}

/** The draft's state and actions: validate against the node, apply (after saying what will
 * change), or throw it away. */
export function DraftBar({
  node,
  device,
  draft,
  source,
  validation,
  onValidated,
  onOutcome,
  onDiscard,
}: Props): ReactNode {
  const [confirming, setConfirming] = useState(false);
  const changes = draftChanges(device, draft);
  const validate = useAction(async () => onValidated(await validatePdos(node, draft)));
  const apply = useAction(async () => {
    const outcome = await applyPdos(node, draft);
    setConfirming(false);
    onOutcome(outcome);
  });

  return (
    <section className="card pdo-draft-bar" aria-label="Draft">
      <header className="card-header">
        <h2>Draft</h2>
        <span className="badge pdo-draft">{source}</span>
        <span className="muted small">
          {changes.length === 0
            ? "Same as the device."
            : `${changes.length === 1 ? "1 PDO differs" : `${changes.length} PDOs differ`} from the device: ${changes.map((c) => pdoLabel(c.pdo)).join(", ")}.`}
        </span>
        {validation && (
          <span className={`badge ${validation.ok ? "pdo-valid" : "pdo-bad"}`} role="status">
            {validation.ok
              ? "Checked: no problems"
              : `${validation.problems.length} problem${validation.problems.length === 1 ? "" : "s"}`}
          </span>
        )}
        <span className="spacer" />
        <button type="button" disabled={validate.busy} onClick={() => void validate.run()}>
          Validate
        </button>
        <button
          type="button"
          className="primary"
          disabled={changes.length === 0}
          onClick={() => {
            apply.clearError();
            setConfirming(true);
          }}
        >
          Apply…
        </button>
        <button type="button" onClick={onDiscard}>
          Discard draft
        </button>
        {validate.busy && <Spinner label="Validating" />}
      </header>
      {draft.some((p) => p.valid && isSynchronous(p.transmission_type)) && <SyncControl />}
      <ErrorText error={validate.error} />
      {confirming && (
        <Dialog
          title={`Apply PDO mapping to node ${node}`}
          onClose={() => setConfirming(false)}
          actions={
            <>
              <button type="button" onClick={() => setConfirming(false)}>
                Cancel
              </button>
              <button
                type="button"
                className="primary"
                disabled={apply.busy}
                onClick={() => void apply.run()}
              >
                Apply
              </button>
              {apply.busy && <Spinner label="Applying" />}
            </>
          }
        >
          <p>
            Node {node} will get these PDO settings. Each changed PDO is made invalid, remapped and
            made valid again; if a step fails, the previous settings are written back.
          </p>
          <ul className="pdo-confirm-list">
            {changes.map(({ pdo, changes: words }) => (
              <li key={`${pdo.kind}${pdo.number}`}>
                <strong>{pdoLabel(pdo)}</strong>: {words.join("; ")}
              </li>
            ))}
          </ul>
          {validation && !validation.ok && (
            <p className="warning">
              The last check found {validation.problems.length} problem
              {validation.problems.length === 1 ? "" : "s"}; the drive will likely refuse it.
            </p>
          )}
          {!validation && <p className="muted small">Not validated yet.</p>}
          <ErrorText error={apply.error} />
        </Dialog>
      )}
    </section>
  );
}
