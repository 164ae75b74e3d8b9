import { useId, type ReactNode } from "react";

import type { ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { formatClock, odAddress } from "../../lib/format";
import { useMay } from "../../session/context";
import { formatReading, isActive, signalKey, triggerText } from "./model";
import { Sparkline } from "./Sparkline";
import type { History } from "./sparkline";
import type { Capture } from "./types";

// arming: the bus is still being set up, or the trigger's signal has not sent a sample yet:
// something that happens now would not trigger the capture
export const STATE_TEXT: Record<Capture["state"], string> = {
  arming: "Arming… (not armed yet)",
  armed: "Armed: waiting for the trigger",
  running: "Recording",
  done: "Done",
  failed: "Failed",
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
          Capture {capture.id}
          {capture.name ? ` · ${capture.name}` : ""}
        </h2>
        <span
          className={`badge scope-state scope-state-${capture.state}`}
          role="status"
          data-testid="capture-state"
        >
          {STATE_TEXT[capture.state]}
        </span>
        <span className="spacer" />
        {active && (
          <button
            type="button"
            className="danger"
            {...operate.gate("stop the capture", { disabled: stopping })}
            onClick={onStop}
          >
            ■ Stop
          </button>
        )}
        {stopping && <Spinner label="Stopping" />}
      </header>
      <ErrorText error={error} />
      <dl className="counters" aria-label="Capture progress">
        <div className="counter">
          <dt>Samples</dt>
          <dd className="num" data-testid="capture-samples">
            {capture.samples.toLocaleString("en-US")}
          </dd>
        </div>
        <div className="counter">
          <dt>Recorded</dt>
          <dd className="num">
            {seconds === null ? "—" : `${seconds.toFixed(1)} of ${capture.duration_s} s`}
          </dd>
        </div>
        <div className="counter">
          <dt>Trigger</dt>
          <dd className="num">
            {capture.trigger_time ? formatClock(capture.trigger_time) : active ? "waiting" : "—"}
          </dd>
        </div>
        {capture.bus_load_percent != null && (
          <div className="counter">
            <dt>Bus load</dt>
            <dd className="num">{capture.bus_load_percent} %</dd>
          </div>
        )}
        {capture.lost > 0 && (
          <div className="counter scope-lost">
            <dt>Lost frames</dt>
            <dd className="num">{capture.lost.toLocaleString("en-US")}</dd>
          </div>
        )}
      </dl>
      <p className="muted small">
        Trigger: {triggerText(capture.trigger)} · SYNC every {capture.sync_period_us} µs
      </p>
      <div className="table-scroll">
        <table className="data-table scope-readouts" aria-label="Live readouts">
          <thead>
            <tr>
              <th>Signal</th>
              <th className="num">Value</th>
              <th>Last readings</th>
              <th className="num">Rate</th>
              <th className="num">Samples</th>
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
                  <td className="num small">{signal.samples.toLocaleString("en-US")}</td>
                </tr>
              );
            })}
          </tbody>
        </table>
      </div>
      {capture.error && <ErrorText error={capture.error} />}
      {notes.length > 0 && (
        <ul className="scope-notes muted small" aria-label="Capture notes">
          {notes.map((note, i) => (
            <li key={i}>{note}</li>
          ))}
        </ul>
      )}
    </section>
  );
}
