import { useMemo, useState, type ReactNode } from "react";

import { jogKeepalive, startJog, stopJog, type JogRamp } from "../../api/driveApi";
import { useLive, useLiveStore } from "../../live/context";
import { useMay } from "../../session/context";
import { HoldButton } from "./HoldButton";
import { KEEPALIVE_TIMEOUT_MS, type HoldSnapshot, type HoldTransport } from "./holdToRun";
import { jogStatus } from "./jogStatus";
import { NumberField } from "./NumberField";
import type { DriveState, JogMode } from "./types";
import { checkRange, formatPct, formatRpm } from "./units";

/** Keep-alives go on the WebSocket while it is open (cheaper), else over REST; a jog the
 * server reported stopped (keep-alive missed, EMCY, quick stop …) ends the hold. */
function useJogTransport(
  node: number,
  mode: JogMode,
  value: () => number,
  ramp: JogRamp,
): HoldTransport {
  const store = useLiveStore();
  return useMemo(
    () => ({
      start: async () => (await startJog(node, mode, value(), KEEPALIVE_TIMEOUT_MS, ramp)).jog_id,
      keepalive: (jogId: string) => {
        const stopped = store.getSnapshot().jogStopped;
        if (stopped?.jog_id === jogId) {
          throw new Error(`Stopped by the server: ${stopped.stop_reason ?? "jog ended"}`);
        }
        if (store.send({ type: "jog_keepalive", jog_id: jogId })) return undefined;
        return jogKeepalive(jogId);
      },
      stop: async (jogId: string) => {
        store.send({ type: "jog_stop", jog_id: jogId });
        await stopJog(jogId);
      },
    }),
    [store, node, mode, value, ramp],
  );
}

const TEXT: Record<JogMode, { what: string; unit: string; initial: string }> = {
  pv: { what: "Speed", unit: "rpm", initial: "60" },
  pt: { what: "Torque", unit: "%", initial: "10" },
};

/** The ramp field of each mode: PV's acceleration (6083h/6084h), PT's torque slope (6087h,
 * counted in 0.1 %/ms: 100 %/s is its finest step). */
const RAMP: Record<
  JogMode,
  { label: string; initial: string; min: number; max: number; title: string }
> = {
  pv: {
    label: "Acceleration (rpm/s)",
    initial: "1000",
    min: 0,
    max: 1_000_000,
    title: "Profile acceleration and deceleration 6083h/6084h: up to speed and back down",
  },
  pt: {
    label: "Torque slope (%/s)",
    initial: "100",
    min: 100,
    max: 100_000,
    title: "Torque slope 6087h (0.1 %/ms: 100 %/s is one step)",
  },
};

/** The torque jog's own speed cap offered first (the server's jog_pt_speed_cap_rpm). */
const DEFAULT_SPEED_CAP_RPM = 300;

/** PV or PT jog: two hold-to-run buttons at the chosen speed or torque. */
export function HoldJog({
  node,
  mode,
  drive,
  mayCommand,
}: {
  node: number;
  mode: JogMode;
  drive: DriveState;
  mayCommand: boolean;
}): ReactNode {
  const text = TEXT[mode];
  const rampText = RAMP[mode];
  const [amount, setAmount] = useState(text.initial);
  const [rampInput, setRampInput] = useState(rampText.initial);
  const speedLimit = drive.limits.max_velocity_rpm;
  const [capInput, setCapInput] = useState(String(Math.min(DEFAULT_SPEED_CAP_RPM, speedLimit)));
  const [hold, setHold] = useState<HoldSnapshot | null>(null);
  const lastJog = useLive((snapshot) => snapshot.jogStopped);
  const max = mode === "pv" ? drive.limits.max_velocity_rpm : drive.limits.max_torque_pct;
  const check = checkRange(amount, { positive: true, max });
  const rampCheck = checkRange(rampInput, {
    positive: true,
    min: mode === "pt" ? rampText.min : null,
    max: rampText.max,
  });
  const capCheck = checkRange(capInput, { positive: true, max: speedLimit });
  const size = check.value ?? 0;
  const rampValue = rampCheck.value;
  const capValue = capCheck.value;
  const ramp = useMemo<JogRamp>(
    () =>
      mode === "pv"
        ? { accelerationRpmS: rampValue }
        : { torqueSlopePctS: rampValue, speedCapRpm: capValue },
    [mode, rampValue, capValue],
  );
  const forward = useJogTransport(
    node,
    mode,
    useMemo(() => () => size, [size]),
    ramp,
  );
  const backward = useJogTransport(
    node,
    mode,
    useMemo(() => () => -size, [size]),
    ramp,
  );
  const enabled = drive.state === "operation_enabled";
  const operate = useMay("operate");
  const why =
    operate.because("jog the drive") ??
    (!mayCommand
      ? "Another client controls this drive"
      : !enabled
        ? "Enable the drive first"
        : (check.error ??
          (rampCheck.error
            ? `${rampText.label}: ${rampCheck.error}`
            : mode === "pt" && capCheck.error
              ? `Speed cap: ${capCheck.error}`
              : null)));
  const id = `jog-${mode}-amount`;
  const cap = drive.pt_speed_limit;
  const status = jogStatus(
    hold?.phase,
    drive.velocity_rpm,
    lastJog !== null && lastJog.node === node && lastJog.mode === mode ? lastJog : null,
    drive.inputs,
  );

  return (
    <div className="hold-jog">
      <div className="drive-form">
        <label htmlFor={id}>
          <span>
            {text.what} ({text.unit})
          </span>
          <input
            id={id}
            className="narrow"
            inputMode="decimal"
            aria-invalid={check.error !== null}
            value={amount}
            onChange={(e) => setAmount(e.target.value)}
          />
        </label>
        <NumberField
          id={`jog-${mode}-ramp`}
          label={rampText.label}
          value={rampInput}
          onChange={setRampInput}
          error={rampCheck.error}
          title={rampText.title}
        />
        {mode === "pt" && (
          <NumberField
            id="jog-pt-speed-cap"
            label="Speed cap (rpm)"
            value={capInput}
            onChange={setCapInput}
            error={capCheck.error}
            title="ServoDesk stops the torque jog when the axis passes this speed"
          />
        )}
        <span className="muted small">
          {mode === "pv"
            ? `limit ${formatRpm(drive.limits.max_velocity_rpm)}`
            : `limit ${formatPct(drive.limits.max_torque_pct)}`}
        </span>
      </div>
      {mode === "pt" && (
        <p className="muted small" data-testid="jog-pt-speed-limit">
          With no load a small torque runs the axis up: ServoDesk stops the jog above the speed cap
          {cap?.rpm != null
            ? `, and the drive itself holds the speed at ${cap.rpm.toFixed(0)} rpm (${cap.source}).`
            : ` (the drive's own limit: ${cap?.source ?? "its max speed object"}).`}
        </p>
      )}
      <div className="hold-row">
        <HoldButton
          label={`◀ Hold −${size || ""} ${text.unit}`}
          transport={backward}
          disabled={why !== null}
          title={why ?? undefined}
          onChange={setHold}
        />
        <HoldButton
          label={`Hold +${size || ""} ${text.unit} ▶`}
          transport={forward}
          disabled={why !== null}
          title={why ?? undefined}
          onChange={setHold}
        />
        <span
          className={status.stopping ? "hold-live stopping-text" : "hold-live"}
          role="status"
          data-testid={`jog-${mode}-status`}
        >
          {status.text}
          {" · "}
          {formatRpm(drive.velocity_rpm)}
          {mode === "pt" && ` · ${formatPct(drive.torque_pct)}`}
          {drive.target_reached && mode === "pv" && hold?.phase === "running" && " · at speed"}
        </span>
      </div>
      {status.reason && !hold?.error && (
        <p className="small" data-testid={`jog-${mode}-stop-reason`}>
          Last jog stopped by itself: {status.reason}
        </p>
      )}
      {why && <p className="muted small">{why}</p>}
      {hold?.error && (
        <p className="error-text" role="alert">
          {hold.error}
        </p>
      )}
      <p className="muted small">
        Hold-to-run: the axis moves only while the button is held (keep-alive every 100 ms; the
        server stops it {KEEPALIVE_TIMEOUT_MS} ms after the last one).
      </p>
    </div>
  );
}
