import { useState, type ReactNode } from "react";
import { Link } from "react-router";

import { runStep, signOffStep } from "../../api/commissionApi";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { StepChip } from "../../components/StatusChip";
import { Trans, useTranslation } from "../../i18n";
import { useAction } from "../../lib/useApi";
import { nodeUrl } from "../../nav/paths";
import { useMay } from "../../session/context";
import { EvidenceView } from "./EvidenceView";
import { FiguresTable } from "./FiguresTable";
import { RunError } from "./RunError";
import { PdoRunInput, RunInputs, runBody, type RunBody, type RunSettings } from "./RunInputs";
import { SkipForm } from "./SkipForm";
import {
  AUTOMATED,
  lostLines,
  MANUAL_PAGE,
  MOVING,
  RUNNING_TEXT,
  stepTitle,
  titleInSentence,
  whoWhen,
} from "./steps";
import type { CommissioningStep, StepKey } from "./types";

export interface StepItemProps {
  node: number;
  recordId: number;
  index: number;
  step: CommissioningStep;
  /** A step of this record is running (only one at a time: they share the axis). */
  running: StepKey | null;
  onRunning: (key: StepKey | null) => void;
  settings: RunSettings;
  onSettings: (settings: RunSettings) => void;
  /** A step changed: the page takes the answer (null: reads the record again) and reloads the
   * record's overall status. */
  onChanged: (step: CommissioningStep | null) => void;
}

/** What a failed store_verify lost, one line each. */
function LostValues({ step }: { step: CommissioningStep }): ReactNode {
  const { t } = useTranslation();
  const lines = lostLines(step);
  if (lines.length === 0) return null;
  return (
    <div className="lost-values" role="alert" aria-label={t("commission.step.lostLabel")}>
      <strong>{t("commission.step.lostHeading")}</strong>
      <ul>
        {lines.map((line) => (
          <li key={line} className="mono">
            {line}
          </li>
        ))}
      </ul>
    </div>
  );
}

/** One step of the flow: status, who and when, figures, evidence and its actions. */
export function StepItem(props: StepItemProps): ReactNode {
  const { node, recordId, index, step, running, onRunning, settings, onSettings, onChanged } =
    props;
  const { t } = useTranslation();
  const title = stepTitle(step);
  const operate = useMay("operate");
  const configure = useMay("configure");
  const [skipping, setSkipping] = useState(false);
  const [invalid, setInvalid] = useState<string | null>(null);
  const automated = AUTOMATED.has(step.key);
  const manual = MANUAL_PAGE[step.key];
  const isRunning = running === step.key;

  const run = useAction(async (body: RunBody) => {
    onRunning(step.key);
    try {
      onChanged(await runStep(recordId, step.key, body));
    } catch (error) {
      onChanged(null); // a run that could not finish may still be recorded failed
      throw error;
    } finally {
      onRunning(null);
    }
  });
  const sign = useAction(async (status: "done" | "skipped", reason?: string) => {
    onChanged(await signOffStep(recordId, step.key, status, reason));
    setSkipping(false);
  });

  function start(): void {
    const built = runBody(step.key, settings);
    if ("invalid" in built) {
      setInvalid(built.invalid);
      return;
    }
    setInvalid(null);
    void run.run(built.body);
  }

  const runPermit = step.key === "store_verify" ? configure : operate;
  const again = step.status !== "to_do";
  const runLabel = again ? t("commission.step.runAgain") : t("commission.step.run");
  const runName = again
    ? t("commission.step.runAgainNamed", { title })
    : t("commission.step.runNamed", { title });
  const busy = running !== null || sign.busy;
  const who = whoWhen(step);
  return (
    <li
      className={`step-item step-item-${step.status}`}
      aria-label={t("commission.step.label", { index, title })}
    >
      <header className="step-header">
        <span className="step-number">{index}</span>
        <h3>{title}</h3>
        <StepChip status={step.status} />
        {who && <span className="muted small">{who}</span>}
      </header>
      {step.reason && (
        <p className={step.status === "failed" ? "step-reason error-text" : "step-reason muted"}>
          {step.status === "failed"
            ? t("commission.step.failed", { reason: step.reason })
            : t("commission.step.reason", { reason: step.reason })}
        </p>
      )}
      <LostValues step={step} />
      <FiguresTable title={title} figures={step.figures} />
      {Object.keys(step.evidence ?? {}).length > 0 && (
        // The moving steps' evidence is long (captures, decelerations): folded until asked.
        <details
          className="step-evidence"
          open={step.status === "failed" || !MOVING.has(step.key) || undefined}
        >
          <summary>{t("commission.step.evidence")}</summary>
          <EvidenceView title={title} evidence={step.evidence} />
        </details>
      )}
      {automated && MOVING.has(step.key) && (
        <RunInputs
          node={node}
          stepKey={step.key}
          settings={settings}
          onChange={onSettings}
          disabled={busy}
        />
      )}
      {automated && step.key === "pdo" && (
        <PdoRunInput
          settings={settings}
          onChange={onSettings}
          disabled={busy}
          mayConfigure={configure.allowed}
        />
      )}
      {manual && (
        <p className="small">
          <Trans
            i18nKey="commission.step.signHere"
            values={{ what: t(manual.label) }}
            components={{ page: <Link to={nodeUrl(node, manual.tab)} /> }}
          />
        </p>
      )}
      <div className="button-row step-actions">
        {automated && (
          <button
            type="button"
            className="primary"
            onClick={start}
            aria-label={runName}
            {...runPermit.gate(t("commission.step.gateRun", { step: titleInSentence(title) }), {
              disabled: busy,
            })}
          >
            {runLabel}
          </button>
        )}
        <button
          type="button"
          onClick={() => void sign.run("done")}
          aria-label={t("commission.step.signOffNamed", { title })}
          {...operate.gate(t("commission.step.gateSignOff"), {
            disabled: busy || step.status === "done",
          })}
        >
          {t("commission.step.signOff")}
        </button>
        <button
          type="button"
          onClick={() => setSkipping((s) => !s)}
          aria-label={t("commission.step.skipNamed", { title })}
          aria-expanded={skipping}
          {...operate.gate(t("commission.step.gateSkip"), { disabled: busy })}
        >
          {t("commission.step.skip")}
        </button>
        {isRunning && (
          <span className="step-running" role="status">
            <Spinner label={t("commission.step.runningNamed", { title })} />{" "}
            {t(RUNNING_TEXT[step.key] ?? "commission.step.running")}
          </span>
        )}
      </div>
      {skipping && (
        <SkipForm
          title={title}
          busy={busy}
          onSkip={(reason) => void sign.run("skipped", reason)}
          onCancel={() => setSkipping(false)}
        />
      )}
      {invalid && <ErrorText error={invalid} />}
      <RunError node={node} error={run.error} />
      <ErrorText error={sign.error} />
    </li>
  );
}
