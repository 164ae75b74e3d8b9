import { Fragment, useId, type ReactNode } from "react";

import type { ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { LoadBar } from "../../components/LoadBar";
import { Spinner } from "../../components/Spinner";
import { formatBitrate, odAddress } from "../../lib/format";
import { signalKey, sourceText } from "./model";
import type { ScopePlan } from "./types";

/** What the capture would do, checked as the selection changes: each signal's source (a TPDO
 * the scope maps, or SDO polling and why), the bus load, problems and notes. */
export function PlanView({
  plan,
  checking,
  error,
  problem,
  paused = false,
  children,
}: {
  plan: ScopePlan | null;
  checking: boolean;
  error: ApiError | null;
  /** Why the form cannot be checked yet (nothing picked, a field out of range). */
  problem: string | null;
  /** A capture is recording: the plan is not re-checked until it ends. */
  paused?: boolean;
  /** The start button row. */
  children?: ReactNode;
}): ReactNode {
  const id = useId();
  const load = plan?.bus_load;
  return (
    <section className="card scope-plan" aria-labelledby={`${id}-h`} aria-busy={checking}>
      <header className="card-header">
        <h2 id={`${id}-h`}>Check</h2>
        {checking && <Spinner label="Checking the capture" />}
        <span className="muted small">
          {checking
            ? "checking…"
            : paused
              ? "not re-checked while a capture records"
              : "checked as you change the selection"}
        </span>
      </header>
      {problem && <p className="muted">{problem}.</p>}
      <ErrorText error={error} />
      {plan && !problem && (
        <div className={checking ? "scope-stale" : undefined}>
          <div className="table-scroll">
            <table className="data-table scope-plan-table" aria-label="Signal sources">
              <thead>
                <tr>
                  <th>Signal</th>
                  <th>Source</th>
                  <th>Unit</th>
                  <th>Note</th>
                </tr>
              </thead>
              <tbody>
                {plan.signals.map((signal) => (
                  <tr key={signalKey(signal)} className={`source-${signal.source}`}>
                    <td>
                      {signal.name}{" "}
                      <span className="mono small muted">
                        {signal.node} · {odAddress(signal.index, signal.subindex)}
                      </span>
                    </td>
                    <td className="scope-source">{sourceText(signal)}</td>
                    <td className="small">{signal.unit || "—"}</td>
                    <td className="small muted">{signal.note ?? ""}</td>
                  </tr>
                ))}
              </tbody>
            </table>
          </div>
          {load && (
            <div className="scope-load">
              <div className="load-rows">
                <span>Bus load</span>
                <LoadBar
                  percent={load.percent}
                  threshold={load.threshold_percent}
                  label="Bus load during the capture"
                />
                <span className="muted small num">
                  {Math.round(load.total_bits_per_s).toLocaleString("en-US")} bit/s of{" "}
                  {formatBitrate(load.bitrate)}
                </span>
                {load.nodes.map((n) => (
                  <Fragment key={n.node}>
                    <span className="muted small">node {n.node}</span>
                    <LoadBar
                      percent={n.percent}
                      threshold={load.threshold_percent}
                      label={`Node ${n.node} load`}
                    />
                    <span className="muted small num">
                      {Math.round(n.bits_per_s).toLocaleString("en-US")} bit/s
                    </span>
                  </Fragment>
                ))}
              </div>
            </div>
          )}
          {plan.problems.length > 0 && (
            <ul className="scope-problems" aria-label="Problems">
              {plan.problems.map((text, i) => (
                <li key={i} className="error-text">
                  {text}
                </li>
              ))}
            </ul>
          )}
          {plan.notes.length > 0 && (
            <ul className="scope-notes muted small" aria-label="Notes">
              {plan.notes.map((text, i) => (
                <li key={i}>{text}</li>
              ))}
            </ul>
          )}
          {load && load.notes.length > 0 && (
            <details className="scope-load-notes">
              <summary>How the load is estimated</summary>
              <ul className="muted small">
                {load.notes.map((text, i) => (
                  <li key={i}>{text}</li>
                ))}
              </ul>
            </details>
          )}
        </div>
      )}
      {children}
    </section>
  );
}
