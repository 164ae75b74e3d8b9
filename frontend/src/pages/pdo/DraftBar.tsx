import { useState, type ReactNode } from "react";

import type { ApiError } from "../../api/errors";
import type { NmtStateName } from "../../api/types";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";
import { draftChanges, isSynchronous, pdoLabel } from "./model";
import { applyPdos, type ApplyOutcome } from "./pdoApi";
import { SyncChoice } from "./SyncChoice";
import type { Pdo, PdoRules, Validation } from "./types";

const DEFAULT_PROCEDURE = "each changed PDO is made invalid, remapped and made valid again";

/** The check's outcome in a few words: problems first, then a SYNC nobody provides. */
function validationWords(validation: Validation): string {
  const count = validation.problems.length;
  if (count > 0) return `${count} problem${count === 1 ? "" : "s"}`;
  if (!validation.ok) return "No SYNC on the bus";
  return "Checked: no problems";
}

/** `text` ending in one full stop. */
function sentence(text: string): string {
  return text.trim().replace(/\.*$/, ".");
}

interface Props {
  node: number;
  device: readonly Pdo[];
  draft: Pdo[];
  source: string;
  /** How the node takes PDOs (undefined while they load). */
  rules: PdoRules | undefined;
  nmtState: NmtStateName | undefined;
  validation: Validation | null;
  validating: boolean;
  validateError: ApiError | null;
  /** SYNC comes from the machine's controller (sent as sync_source "external"). */
  syncExternal: boolean;
  onSyncExternal: (external: boolean) => void;
  onValidate: () => void;
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
  rules,
  nmtState,
  validation,
  validating,
  validateError,
  syncExternal,
  onSyncExternal,
  onValidate,
  onOutcome,
  onDiscard,
}: Props): ReactNode {
  const configure = useMay("configure");
  const [confirming, setConfirming] = useState(false);
  const changes = draftChanges(device, draft);
  const synchronous = draft.some((p) => p.valid && isSynchronous(p.transmission_type));
  const apply = useAction(async () => {
    const outcome = await applyPdos(node, draft, syncExternal ? "external" : null);
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
            {validationWords(validation)}
          </span>
        )}
        <span className="spacer" />
        <button type="button" disabled={validating} onClick={onValidate}>
          Validate
        </button>
        <button
          type="button"
          className="primary"
          {...configure.gate("apply a PDO mapping", { disabled: changes.length === 0 })}
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
        {validating && <Spinner label="Validating" />}
      </header>
      <SyncChoice
        draft={draft}
        validation={validation}
        external={syncExternal}
        onExternal={onSyncExternal}
        onSyncStarted={() => {
          if (validation) onValidate();
        }}
      />
      <ErrorText error={validateError} />
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
          <p>Node {node} will get these PDO settings:</p>
          <ul className="pdo-confirm-list">
            {changes.map(({ pdo, changes: words }) => (
              <li key={`${pdo.kind}${pdo.number}`}>
                <strong>{pdoLabel(pdo)}</strong>: {words.join("; ")}
              </li>
            ))}
          </ul>
          <p className="pdo-procedure">
            <strong>How node {node} takes the new mapping:</strong>{" "}
            {sentence(rules?.procedure ?? DEFAULT_PROCEDURE)} If a step fails, the previous settings
            are written back.
          </p>
          {rules?.needs_pre_operational && nmtState === "operational" && (
            <p className="warning">
              Node {node} is operational: it goes to pre-operational for the change, so it neither
              sends nor takes PDOs until it is back.
            </p>
          )}
          {validation && validation.problems.length > 0 && (
            <p className="warning">
              The last check found {validation.problems.length} problem
              {validation.problems.length === 1 ? "" : "s"}; the drive will likely refuse it.
            </p>
          )}
          {synchronous &&
            (syncExternal ? (
              <p className="small">SYNC comes from the machine&apos;s controller (PLC).</p>
            ) : (
              validation &&
              !validation.ok &&
              validation.problems.length === 0 && (
                <p className="warning">
                  No SYNC is produced or heard on the bus: start the SYNC producer, or say that SYNC
                  comes from the machine&apos;s controller.
                </p>
              )
            ))}
          {!validation && <p className="muted small">Not validated yet.</p>}
          <ErrorText error={apply.error} />
        </Dialog>
      )}
    </section>
  );
}
