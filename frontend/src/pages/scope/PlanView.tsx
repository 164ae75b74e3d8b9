import { Fragment, useId, type ReactNode } from "react";

import type { ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { LoadBar } from "../../components/LoadBar";
import { Spinner } from "../../components/Spinner";
import { currentLocale, useTranslation } from "../../i18n";
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
  const { t } = useTranslation();
  const id = useId();
  const load = plan?.bus_load;
  return (
    <section className="card scope-plan" aria-labelledby={`${id}-h`} aria-busy={checking}>
      <header className="card-header">
        <h2 id={`${id}-h`}>{t("scope.plan.heading")}</h2>
        {checking && <Spinner label={t("scope.plan.checkingLabel")} />}
        <span className="muted small">
          {checking
            ? t("scope.plan.checking")
            : paused
              ? t("scope.plan.paused")
              : t("scope.plan.live")}
        </span>
      </header>
      {problem && <p className="muted">{t("scope.problem.shown", { problem })}</p>}
      <ErrorText error={error} />
      {plan && !problem && (
        <div className={checking ? "scope-stale" : undefined}>
          <div className="table-scroll">
            <table className="data-table scope-plan-table" aria-label={t("scope.plan.sources")}>
              <thead>
                <tr>
                  <th>{t("scope.plan.signal")}</th>
                  <th>{t("scope.plan.source")}</th>
                  <th>{t("scope.plan.unit")}</th>
                  <th>{t("scope.plan.note")}</th>
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
                <span>{t("scope.plan.busLoad")}</span>
                <LoadBar
                  percent={load.percent}
                  threshold={load.threshold_percent}
                  label={t("scope.plan.busLoadLabel")}
                />
                <span className="muted small num">
                  {t("scope.plan.bitsOf", {
                    bits: Math.round(load.total_bits_per_s).toLocaleString(currentLocale()),
                    bitrate: formatBitrate(load.bitrate),
                  })}
                </span>
                {load.nodes.map((n) => (
                  <Fragment key={n.node}>
                    <span className="muted small">
                      {t("scope.plan.nodeLoad", { node: n.node })}
                    </span>
                    <LoadBar
                      percent={n.percent}
                      threshold={load.threshold_percent}
                      label={t("scope.plan.nodeLoadLabel", { node: n.node })}
                    />
                    <span className="muted small num">
                      {t("scope.plan.bits", {
                        bits: Math.round(n.bits_per_s).toLocaleString(currentLocale()),
                      })}
                    </span>
                  </Fragment>
                ))}
              </div>
            </div>
          )}
          {plan.problems.length > 0 && (
            <ul className="scope-problems" aria-label={t("scope.plan.problems")}>
              {plan.problems.map((text, i) => (
                <li key={i} className="error-text">
                  {text}
                </li>
              ))}
            </ul>
          )}
          {plan.notes.length > 0 && (
            <ul className="scope-notes muted small" aria-label={t("scope.plan.notes")}>
              {plan.notes.map((text, i) => (
                <li key={i}>{text}</li>
              ))}
            </ul>
          )}
          {load && load.notes.length > 0 && (
            <details className="scope-load-notes">
              <summary>{t("scope.plan.howLoad")}</summary>
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
