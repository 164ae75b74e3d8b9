import { useState, type ReactNode } from "react";
import { Link } from "react-router";

import { runStep, signOffStep } from "../../api/commissionApi";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { StepChip } from "../../components/StatusChip";
import { useAction } from "../../lib/useApi";
import { nodeUrl } from "../../nav/paths";
import { useMay } from "../../session/context";
import { EvidenceView } from "./EvidenceView";
import { FiguresTable } from "./FiguresTable";
import { RunError } from "./RunError";
import { PdoRunInput, RunInputs, runBody, type RunBody, type RunSettings } from "./RunInputs";
import { SkipForm } from "./SkipForm";
import { AUTOMATED, lostLines, MANUAL_PAGE, MOVING, RUNNING_TEXT, whoWhen } from "./steps";
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
  const lines = lostLines(step);
  if (lines.length === 0) return null;
  return (
    <div className="lost-values" role="alert" aria-label="Values lost over the reset">
      <strong>Not kept over the reset:</strong>
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
  const runLabel = step.status === "to_do" ? "Run" : "Run again";
  const busy = running !== null || sign.busy;
  const who = whoWhen(step);
  return (
    <li
      className={`step-item step-item-${step.status}`}
      aria-label={`Step ${index}: ${step.title}`}
    >
      <header className="step-header">
        <span className="step-number">{index}</span>
        <h3>{step.title}</h3>
        <StepChip status={step.status} />
        {who && <span className="muted small">{who}</span>}
      </header>
      {step.reason && (
        <p className={step.status === "failed" ? "step-reason error-text" : "step-reason muted"}>
          {step.status === "failed" ? "Failed: " : "Reason: "}
          {step.reason}
        </p>
      )}
      <LostValues step={step} />
      <FiguresTable title={step.title} figures={step.figures} />
      {Object.keys(step.evidence ?? {}).length > 0 && (
        // The moving steps' evidence is long (captures, decelerations): folded until asked.
        <details
          className="step-evidence"
          open={step.status === "failed" || !MOVING.has(step.key) || undefined}
        >
          <summary>Evidence</summary>
          <EvidenceView title={step.title} evidence={step.evidence} />
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
          <Link to={nodeUrl(node, manual.tab)}>{manual.label}</Link>, then sign this step off here.
        </p>
      )}
      <div className="button-row step-actions">
        {automated && (
          <button
            type="button"
            className="primary"
            onClick={start}
            aria-label={`${runLabel} ${step.title}`}
            {...runPermit.gate(`run ${step.title.toLowerCase()}`, { disabled: busy })}
          >
            {runLabel}
          </button>
        )}
        <button
          type="button"
          onClick={() => void sign.run("done")}
          aria-label={`Sign off ${step.title}`}
          {...operate.gate("sign a step off", { disabled: busy || step.status === "done" })}
        >
          Sign off
        </button>
        <button
          type="button"
          onClick={() => setSkipping((s) => !s)}
          aria-label={`Skip ${step.title}…`}
          aria-expanded={skipping}
          {...operate.gate("skip a step", { disabled: busy })}
        >
          Skip…
        </button>
        {isRunning && (
          <span className="step-running" role="status">
            <Spinner label={`Running ${step.title}`} /> {RUNNING_TEXT[step.key] ?? "Running…"}
          </span>
        )}
      </div>
      {skipping && (
        <SkipForm
          title={step.title}
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
