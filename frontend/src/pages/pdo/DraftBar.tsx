import { useState, type ReactNode } from "react";

import type { ApiError } from "../../api/errors";
import type { NmtStateName } from "../../api/types";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { i18n, useTranslation } from "../../i18n";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";
import { draftChanges, isSynchronous, pdoLabel } from "./model";
import { applyPdos, type ApplyOutcome } from "./pdoApi";
import { SyncChoice } from "./SyncChoice";
import type { Pdo, PdoRules, Validation } from "./types";

/** The check's outcome in a few words: problems first, then a SYNC nobody provides. */
function validationWords(validation: Validation): string {
  const count = validation.problems.length;
  if (count > 0) return i18n.t("pdo.draft.problems", { count });
  if (!validation.ok) return i18n.t("pdo.draft.noSync");
  return i18n.t("pdo.draft.checked");
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
  const { t } = useTranslation();
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
    <section className="card pdo-draft-bar" aria-label={t("pdo.draft.heading")}>
      <header className="card-header">
        <h2>{t("pdo.draft.heading")}</h2>
        <span className="badge pdo-draft">{source}</span>
        <span className="muted small">
          {changes.length === 0
            ? t("pdo.draft.same")
            : t("pdo.draft.differs", {
                count: changes.length,
                pdos: changes.map((c) => pdoLabel(c.pdo)).join(t("common.listSeparator")),
              })}
        </span>
        {validation && (
          <span className={`badge ${validation.ok ? "pdo-valid" : "pdo-bad"}`} role="status">
            {validationWords(validation)}
          </span>
        )}
        <span className="spacer" />
        <button type="button" disabled={validating} onClick={onValidate}>
          {t("pdo.draft.validate")}
        </button>
        <button
          type="button"
          className="primary"
          {...configure.gate(t("pdo.draft.gateApply"), { disabled: changes.length === 0 })}
          onClick={() => {
            apply.clearError();
            setConfirming(true);
          }}
        >
          {t("pdo.draft.apply")}
        </button>
        <button type="button" onClick={onDiscard}>
          {t("pdo.draft.discard")}
        </button>
        {validating && <Spinner label={t("pdo.draft.validating")} />}
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
          title={t("pdo.draft.dialogTitle", { node })}
          onClose={() => setConfirming(false)}
          actions={
            <>
              <button type="button" onClick={() => setConfirming(false)}>
                {t("pdo.draft.cancel")}
              </button>
              <button
                type="button"
                className="primary"
                disabled={apply.busy}
                onClick={() => void apply.run()}
              >
                {t("pdo.draft.confirm")}
              </button>
              {apply.busy && <Spinner label={t("pdo.draft.applying")} />}
            </>
          }
        >
          <p>{t("pdo.draft.willGet", { node })}</p>
          <ul className="pdo-confirm-list">
            {changes.map(({ pdo, changes: words }) => (
              <li key={`${pdo.kind}${pdo.number}`}>
                <strong>{pdoLabel(pdo)}</strong>: {words.join(t("pdo.card.changeSeparator"))}
              </li>
            ))}
          </ul>
          <p className="pdo-procedure">
            <strong>{t("pdo.draft.howTakes", { node })}</strong>{" "}
            {rules?.procedure ? sentence(rules.procedure) : t("pdo.draft.defaultProcedure")}{" "}
            {t("pdo.draft.rollback")}
          </p>
          {rules?.needs_pre_operational && nmtState === "operational" && (
            <p className="warning">{t("pdo.draft.operational", { node })}</p>
          )}
          {validation && validation.problems.length > 0 && (
            <p className="warning">
              {t("pdo.draft.lastCheck", { count: validation.problems.length })}
            </p>
          )}
          {synchronous &&
            (syncExternal ? (
              <p className="small">{t("pdo.draft.syncExternal")}</p>
            ) : (
              validation &&
              !validation.ok &&
              validation.problems.length === 0 && (
                <p className="warning">{t("pdo.draft.noSyncWarning")}</p>
              )
            ))}
          {!validation && <p className="muted small">{t("pdo.draft.notValidated")}</p>}
          <ErrorText error={apply.error} />
        </Dialog>
      )}
    </section>
  );
}
