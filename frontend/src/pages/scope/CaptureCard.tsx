import { useId, type ReactNode } from "react";

import type { ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { currentLocale, useTranslation, type MessageKey } from "../../i18n";
import { formatClock, odAddress } from "../../lib/format";
import { useMay } from "../../session/context";
import { formatReading, isActive, signalKey, triggerText } from "./model";
import { Sparkline } from "./Sparkline";
import type { History } from "./sparkline";
import type { Capture } from "./types";

// arming: the bus is still being set up, or the trigger's signal has not sent a sample yet:
// something that happens now would not trigger the capture
export const STATE_TEXT: Record<Capture["state"], MessageKey> = {
  arming: "scope.state.arming",
  armed: "scope.state.armed",
  running: "scope.state.running",
  done: "scope.state.done",
  failed: "scope.state.failed",
};

/** Seconds recorded so far (from the trigger, or the start while armed), at most the duration. */
function elapsed(capture: Capture, now: number): number | null {
  const from = capture.trigger_time ?? null;
  if (from === null) return null;
  const to = capture.ended ?? now;
  return Math.max(0, Math.min(capture.duration_s, to - from));
}

/** The capture being recorded (or the last one): state, samples, per-signal readouts. */
export function CaptureCard({
  capture,
  history,
  now,
  onStop,
  stopping,
  error,
}: {
  capture: Capture;
  history: History;
  /** Epoch seconds of the last poll (the elapsed time moves with it). */
  now: number;
  onStop: () => void;
  stopping: boolean;
  error: ApiError | null;
}): ReactNode {
  const { t } = useTranslation();
  const id = useId();
  const operate = useMay("operate");
  const active = isActive(capture);
  const seconds = elapsed(capture, now);
  const values = history.capture === capture.id ? history.values : {};
  const notes = capture.notes ?? [];
  return (
    <section className="card scope-capture" aria-labelledby={`${id}-h`}>
      <header className="card-header">
        <h2 id={`${id}-h`}>
          {capture.name
            ? t("scope.capture.headingNamed", { id: capture.id, name: capture.name })
            : t("scope.capture.heading", { id: capture.id })}
        </h2>
        <span
          className={`badge scope-state scope-state-${capture.state}`}
          role="status"
          data-testid="capture-state"
        >
          {t(STATE_TEXT[capture.state])}
        </span>
        <span className="spacer" />
        {active && (
          <button
            type="button"
            className="danger"
            {...operate.gate(t("scope.capture.gateStop"), { disabled: stopping })}
            onClick={onStop}
          >
            {t("scope.capture.stop")}
          </button>
        )}
        {stopping && <Spinner label={t("scope.capture.stopping")} />}
      </header>
      <ErrorText error={error} />
      <dl className="counters" aria-label={t("scope.capture.progress")}>
        <div className="counter">
          <dt>{t("scope.capture.samples")}</dt>
          <dd className="num" data-testid="capture-samples">
            {capture.samples.toLocaleString(currentLocale())}
          </dd>
        </div>
        <div className="counter">
          <dt>{t("scope.capture.recorded")}</dt>
          <dd className="num">
            {seconds === null
              ? "—"
              : t("scope.capture.recordedOf", {
                  seconds: seconds.toFixed(1),
                  duration: capture.duration_s,
                })}
          </dd>
        </div>
        <div className="counter">
          <dt>{t("scope.capture.trigger")}</dt>
          <dd className="num">
            {capture.trigger_time
              ? formatClock(capture.trigger_time)
              : active
                ? t("scope.capture.waiting")
                : "—"}
          </dd>
        </div>
        {capture.bus_load_percent != null && (
          <div className="counter">
            <dt>{t("scope.capture.busLoad")}</dt>
            <dd className="num">{capture.bus_load_percent} %</dd>
          </div>
        )}
        {capture.lost > 0 && (
          <div className="counter scope-lost">
            <dt>{t("scope.capture.lost")}</dt>
            <dd className="num">{capture.lost.toLocaleString(currentLocale())}</dd>
          </div>
        )}
      </dl>
      <p className="muted small">
        {t("scope.capture.triggerLine", {
          trigger: triggerText(capture.trigger),
          period: capture.sync_period_us,
        })}
      </p>
      <div className="table-scroll">
        <table className="data-table scope-readouts" aria-label={t("scope.capture.readouts")}>
          <thead>
            <tr>
              <th>{t("scope.capture.signal")}</th>
              <th className="num">{t("scope.capture.value")}</th>
              <th>{t("scope.capture.lastReadings")}</th>
              <th className="num">{t("scope.capture.rate")}</th>
              <th className="num">{t("scope.capture.samples")}</th>
            </tr>
          </thead>
          <tbody>
            {capture.signals.map((signal) => {
              const key = signalKey(signal);
              return (
                <tr key={key}>
                  <td>
                    {signal.name}{" "}
                    <span className="mono small muted">
                      {signal.node} · {odAddress(signal.index, signal.subindex)}
                    </span>
                    {signal.note && <span className="block muted small">{signal.note}</span>}
                  </td>
                  <td className="num scope-value">{formatReading(signal.last_value, signal)}</td>
                  <td className="scope-trend">
                    <Sparkline values={values[key] ?? []} label={signal.name} />
                  </td>
                  <td className="num small">
                    {signal.rate_hz == null ? "—" : `${Math.round(signal.rate_hz)} Hz`}
                  </td>
                  <td className="num small">{signal.samples.toLocaleString(currentLocale())}</td>
                </tr>
              );
            })}
          </tbody>
        </table>
      </div>
      {capture.error && <ErrorText error={capture.error} />}
      {notes.length > 0 && (
        <ul className="scope-notes muted small" aria-label={t("scope.capture.notes")}>
          {notes.map((note, i) => (
            <li key={i}>{note}</li>
          ))}
        </ul>
      )}
    </section>
  );
}
