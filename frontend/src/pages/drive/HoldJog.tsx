import { useMemo, useState, type ReactNode } from "react";

import { jogKeepalive, startJog, stopJog, type JogRamp } from "../../api/driveApi";
import { i18n, useTranslation, type MessageKey } from "../../i18n";
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
          const reason = stopped.stop_reason ?? i18n.t("drive.hold.jogEnded");
          throw new Error(i18n.t("drive.hold.serverStopped", { reason }));
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

const TEXT: Record<JogMode, { what: MessageKey; unit: string; initial: string }> = {
  pv: { what: "drive.hold.speed", unit: "rpm", initial: "60" },
  pt: { what: "drive.hold.torque", unit: "%", initial: "10" },
};

/** The ramp field of each mode: PV's acceleration (6083h/6084h), PT's torque slope (6087h,
 * counted in 0.1 %/ms: 100 %/s is its finest step). */
const RAMP: Record<
  JogMode,
  { label: MessageKey; initial: string; min: number; max: number; title: MessageKey }
> = {
  pv: {
    label: "drive.hold.acceleration",
    initial: "1000",
    min: 0,
    max: 1_000_000,
    title: "drive.hold.accelerationTitle",
  },
  pt: {
    label: "drive.hold.slope",
    initial: "100",
    min: 100,
    max: 100_000,
    title: "drive.hold.slopeTitle",
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
  const { t } = useTranslation();
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
  const enabled = drive.state === "operation_enabled";
  const operate = useMay("operate");
  // the reason first: t() takes the checks' texts before the memo below reads their values
  const why =
    operate.because(t("drive.hold.gate")) ??
    (!mayCommand
      ? t("drive.hold.otherClient")
      : !enabled
        ? t("drive.hold.enableFirst")
        : (check.error ??
          (rampCheck.error
            ? t("drive.hold.fieldError", { field: t(rampText.label), error: rampCheck.error })
            : mode === "pt" && capCheck.error
              ? t("drive.hold.speedCapError", { error: capCheck.error })
              : null)));
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
          <span>{t(text.what)}</span>
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
          label={t(rampText.label)}
          value={rampInput}
          onChange={setRampInput}
          error={rampCheck.error}
          title={t(rampText.title)}
        />
        {mode === "pt" && (
          <NumberField
            id="jog-pt-speed-cap"
            label={t("drive.hold.speedCap")}
            value={capInput}
            onChange={setCapInput}
            error={capCheck.error}
            title={t("drive.hold.speedCapTitle")}
          />
        )}
        <span className="muted small">
          {t("drive.hold.limit", {
            value:
              mode === "pv"
                ? formatRpm(drive.limits.max_velocity_rpm)
                : formatPct(drive.limits.max_torque_pct),
          })}
        </span>
      </div>
      {mode === "pt" && (
        <p className="muted small" data-testid="jog-pt-speed-limit">
          {cap?.rpm != null
            ? t("drive.hold.ptHeld", { rpm: cap.rpm.toFixed(0), source: cap.source })
            : t("drive.hold.ptOwn", { source: cap?.source ?? t("drive.hold.ptOwnDefault") })}
        </p>
      )}
      <div className="hold-row">
        <HoldButton
          label={t("drive.hold.back", { size: size || "", unit: text.unit })}
          transport={backward}
          disabled={why !== null}
          title={why ?? undefined}
          onChange={setHold}
        />
        <HoldButton
          label={t("drive.hold.forward", { size: size || "", unit: text.unit })}
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
          {drive.target_reached &&
            mode === "pv" &&
            hold?.phase === "running" &&
            ` · ${t("drive.hold.atSpeed")}`}
        </span>
      </div>
      {status.reason && !hold?.error && (
        <p className="small" data-testid={`jog-${mode}-stop-reason`}>
          {t("drive.hold.lastStopped", { reason: status.reason })}
        </p>
      )}
      {why && <p className="muted small">{why}</p>}
      {hold?.error && (
        <p className="error-text" role="alert">
          {hold.error}
        </p>
      )}
      <p className="muted small">{t("drive.hold.note", { ms: KEEPALIVE_TIMEOUT_MS })}</p>
    </div>
  );
}
