import { useEffect, useRef, useState, type ReactNode } from "react";

import { home, homingMethods } from "../../api/driveApi";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation, type MessageKey } from "../../i18n";
import { useAction, useApi } from "../../lib/useApi";
import { useLive } from "../../live/context";
import { useMay } from "../../session/context";
import { HomingDiagram } from "./HomingDiagram";
import { HomingTimeline } from "./HomingTimeline";
import { methodDescription, methodName } from "./homingWords";
import { manualFor } from "./manuals";
import { NumberField } from "./NumberField";
import { homingStatus } from "./statusBits";
import { addSample, type Sample } from "./timeline";
import type { DriveState, HomeRequest } from "./types";
import { checkRange, formatInc, formatRev } from "./units";

const PHASE_TEXT: Record<"running" | "attained" | "error" | "interrupted", MessageKey> = {
  running: "drive.homing.running",
  attained: "drive.homing.attained",
  error: "drive.homing.error",
  interrupted: "drive.homing.interrupted",
};

/** Records the statusword while a run is on, for the timeline. */
function useRunSamples(drive: DriveState, runStart: number | null): Sample[] {
  const [samples, setSamples] = useState<Sample[]>([]);
  const lastRun = useRef<number | null>(null);
  useEffect(() => {
    if (runStart === null) return;
    const fresh = lastRun.current !== runStart;
    lastRun.current = runStart;
    const sample = { t: Date.now() - runStart, statusword: drive.statusword };
    setSamples((old) => addSample(fresh ? [] : old, sample));
  }, [drive, runStart]);
  return runStart === null ? [] : samples;
}

/** Pick a method the drive supports (each drawn as its path), set speeds, start, watch. */
export function HomingWizard({
  node,
  drive,
  show,
  mayCommand,
}: {
  node: number;
  drive: DriveState;
  show: (state: DriveState) => void;
  mayCommand: boolean;
}): ReactNode {
  const { t } = useTranslation();
  const methods = useApi((signal) => homingMethods(node, signal), `homing:${node}`);
  const profile = useLive((s) => s.infos.find((i) => i.node === node)?.profile);
  const [picked, setPicked] = useState<number | null>(null);
  const operate = useMay("operate");
  const [fast, setFast] = useState("100");
  const [slow, setSlow] = useState("20");
  const [accel, setAccel] = useState("500");
  const [offset, setOffset] = useState("0");
  const [runStart, setRunStart] = useState<number | null>(null);
  const samples = useRunSamples(drive, runStart);
  const start = useAction(async (request: HomeRequest) => {
    setRunStart(Date.now());
    show(await home(node, request));
  });

  const list = methods.data ?? [];
  const method = list.find((m) => m.method === picked) ?? list[0];
  const f = checkRange(fast, { positive: true, max: drive.limits.max_velocity_rpm });
  const s = checkRange(slow, { positive: true, max: drive.limits.max_velocity_rpm });
  const a = checkRange(accel, { positive: true });
  const o = checkRange(offset, {});
  const valid = [f, s, a, o].every((c) => c.error === null);
  const enabled = drive.state === "operation_enabled";
  const homing = drive.homing;
  const running = homing?.phase === "running";
  const status = homingStatus(drive.statusword);

  return (
    <section className="card drive-homing" aria-labelledby="drive-homing-heading">
      <header className="card-header">
        <h2 id="drive-homing-heading">{t("drive.homing.heading")}</h2>
        <span className="muted small">{manualFor(profile, "homing")}</span>
      </header>
      <ErrorText error={methods.error} onRetry={methods.reload} />
      {methods.loading && !methods.data && <Spinner label={t("drive.homing.loading")} />}
      {list.length > 0 && (
        <div className="homing-methods" role="radiogroup" aria-label={t("drive.homing.method")}>
          {list.map((m) => (
            <label
              key={m.method}
              className={m.method === method?.method ? "homing-method picked" : "homing-method"}
            >
              <span className="homing-method-title">
                <input
                  type="radio"
                  name={`homing-${node}`}
                  checked={m.method === method?.method}
                  onChange={() => setPicked(m.method)}
                />
                <strong>{m.method}</strong> {methodName(m)}
              </span>
              <HomingDiagram method={m} />
              <span className="muted small">{methodDescription(m)}</span>
            </label>
          ))}
        </div>
      )}
      <div className="drive-form">
        <NumberField
          label={t("drive.homing.fast")}
          value={fast}
          onChange={setFast}
          error={f.error}
          title={t("drive.homing.fastTitle")}
        />
        <NumberField
          label={t("drive.homing.slow")}
          value={slow}
          onChange={setSlow}
          error={s.error}
          title={t("drive.homing.slowTitle")}
        />
        <NumberField
          label={t("drive.homing.acceleration")}
          value={accel}
          onChange={setAccel}
          error={a.error}
          title={t("drive.homing.accelerationTitle")}
        />
        <NumberField
          label={t("drive.homing.offset")}
          value={offset}
          onChange={setOffset}
          error={o.error}
          title={t("drive.homing.offsetTitle")}
        />
        <button
          type="button"
          className="primary"
          {...operate.gate(t("drive.homing.gate"), {
            disabled: !method || !valid || !enabled || !mayCommand || start.busy || running,
          })}
          onClick={() =>
            method &&
            void start.run({
              method: method.method,
              fast_rpm: f.value ?? undefined,
              slow_rpm: s.value ?? undefined,
              acceleration_rpm_s: a.value ?? undefined,
              offset_inc: Math.round(o.value ?? 0),
            })
          }
        >
          {method
            ? t("drive.homing.startMethod", { method: method.method })
            : t("drive.homing.start")}
        </button>
      </div>
      {!enabled && <p className="muted small">{t("drive.homing.enableToHome")}</p>}
      <ErrorText error={start.error} />
      {homing && (
        <div
          className={`homing-progress ${homing.phase}`}
          role="status"
          data-testid="homing-progress"
        >
          <strong>{t(PHASE_TEXT[homing.phase])}</strong> ·{" "}
          {t("drive.homing.methodNumber", { method: homing.method })}
          {homing.message && <span> · {homing.message}</span>}
          {homing.phase === "attained" && (
            <span data-testid="homing-result">
              {" "}
              ·{" "}
              {t("drive.homing.homeAt", {
                position: formatInc(homing.position_inc ?? drive.position_inc),
                now: formatRev(drive.position_rev),
              })}
            </span>
          )}
          {homing.phase === "running" && (
            <span className={`badge drive-${status.tone}`}>{status.text}</span>
          )}
        </div>
      )}
      {samples.length > 0 && <HomingTimeline samples={samples} />}
    </section>
  );
}
