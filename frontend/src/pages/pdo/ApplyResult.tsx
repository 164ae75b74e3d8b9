import type { ReactNode } from "react";

import { formatAbortCode } from "../../api/errors";
import type { ApplyOutcome } from "./pdoApi";

/** What came of the last apply: the read-back, or the step that failed and what was restored. */
export function ApplyResult({
  outcome,
  onClose,
}: {
  outcome: ApplyOutcome;
  onClose: () => void;
}): ReactNode {
  const close = (
    <button type="button" className="small" onClick={onClose}>
      Dismiss
    </button>
  );
  if (outcome.result === "applied") {
    const valid = outcome.pdos.filter((p) => p.valid).length;
    return (
      <section className="card notice" role="status" aria-label="Apply result">
        <header className="card-header">
          <h2>Applied</h2>
          <span className="spacer" />
          {close}
        </header>
        <p>
          Read back from the device: {outcome.pdos.length} PDOs, {valid} valid. The PDOs below show
          what the device now has.
        </p>
      </section>
    );
  }
  if (outcome.result === "rejected") {
    return (
      <section className="card pdo-failure" role="alert" aria-label="Apply result">
        <header className="card-header">
          <h2>Not applied</h2>
          <span className="spacer" />
          {close}
        </header>
        <p>{outcome.message}</p>
        <p className="small">
          Each problem is shown below at the PDO, field or mapped object it is about.
        </p>
      </section>
    );
  }
  const { failure } = outcome;
  return (
    <section className="card pdo-failure" role="alert" aria-label="Apply result">
      <header className="card-header">
        <h2>Apply failed</h2>
        <span className="spacer" />
        {close}
      </header>
      <dl className="facts">
        <dt>Step</dt>
        <dd>{failure.step}</dd>
        <dt>Answer</dt>
        <dd className="error-text">
          {failure.abort_code && (
            <span className="mono">{formatAbortCode(failure.abort_code)} — </span>
          )}
          {failure.message}
        </dd>
        <dt>Device</dt>
        <dd>
          {failure.restored
            ? "Restored: the previous PDO settings were written back."
            : "Not restored: the PDOs may be half-configured. Read them again and check before starting the node."}
        </dd>
      </dl>
    </section>
  );
}
