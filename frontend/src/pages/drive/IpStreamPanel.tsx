import { useState, type ReactNode } from "react";

import { ipStream } from "../../api/driveApi";
import type { ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";
import type { DriveState, IpStreamResult, IpTrajectory } from "./types";
import { checkRange, formatInc, formatMs, formatRev } from "./units";

/** The server refused the stream before sending anything: this computer did not keep the
 * SYNC deadlines (409 sync_unsafe, whose message names the measured jitter). */
function syncUnsafe(error: ApiError | null): boolean {
  return error !== null && error.status === 409 && error.message.includes("SYNC timing");
}

/** Interpolated position: stream a point-to-point or sine trajectory with SYNC at 2 or 10 ms,
 * then show how closely the axis followed and how regular the SYNC was. A stream the server
 * refused, or one that stalled or faulted, says so first. */
export function IpStreamPanel({
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
  const [trajectory, setTrajectory] = useState<IpTrajectory>("point_to_point");
  const [period, setPeriod] = useState(10);
  const [distance, setDistance] = useState("2");
  const [duration, setDuration] = useState("2");
  const [result, setResult] = useState<IpStreamResult | null>(null);
  const dist = checkRange(distance, {});
  const dur = checkRange(duration, { positive: true, max: 30 });
  const run = useAction(async () => {
    setResult(null);
    const answer = await ipStream(node, {
      trajectory,
      period_ms: period,
      distance_rev: dist.value ?? 0,
      duration_s: dur.value ?? 1,
    });
    setResult(answer);
    show(answer.state);
  });
  const enabled = drive.state === "operation_enabled";
  const ok = dist.value !== null && dur.value !== null && enabled && mayCommand;
  const operate = useMay("operate");

  return (
    <div className="ip-stream">
      <div className="drive-form">
        <label>
          <span>{t("drive.ip.trajectory")}</span>
          <select
            value={trajectory}
            onChange={(e) => setTrajectory(e.target.value as IpTrajectory)}
          >
            <option value="point_to_point">{t("drive.ip.pointToPoint")}</option>
            <option value="sine">{t("drive.ip.sine")}</option>
          </select>
        </label>
        <fieldset className="inline">
          <legend className="visually-hidden">{t("drive.ip.syncPeriod")}</legend>
          {[2, 10].map((ms) => (
            <label key={ms} className="check">
              <input
                type="radio"
                name={`ip-period-${node}`}
                checked={period === ms}
                onChange={() => setPeriod(ms)}
              />
              {ms} ms
            </label>
          ))}
        </fieldset>
        <label>
          <span>{t("drive.ip.distance")}</span>
          <input
            className="narrow"
            inputMode="decimal"
            aria-invalid={dist.error !== null}
            value={distance}
            onChange={(e) => setDistance(e.target.value)}
          />
        </label>
        <label>
          <span>{t("drive.ip.duration")}</span>
          <input
            className="narrow"
            inputMode="decimal"
            aria-invalid={dur.error !== null}
            value={duration}
            onChange={(e) => setDuration(e.target.value)}
          />
        </label>
        <button
          type="button"
          className="primary"
          {...operate.gate(t("drive.ip.gate"), { disabled: !ok || run.busy })}
          onClick={() => void run.run()}
        >
          {t("drive.ip.run")}
        </button>
        {run.busy && <Spinner label={t("drive.ip.streaming")} />}
      </div>
      {!enabled && <p className="muted small">{t("drive.ip.enableToStream")}</p>}
      {syncUnsafe(run.error) ? (
        <div className="ip-result bad" role="alert" data-testid="ip-refused">
          <p>
            <strong>{t("drive.ip.refused")}</strong>
          </p>
          <p>{run.error?.message}</p>
          {period === 2 && (
            <button type="button" onClick={() => setPeriod(10)}>
              {t("drive.ip.use10")}
            </button>
          )}
        </div>
      ) : (
        <ErrorText error={run.error} />
      )}
      {result && (
        <div
          className={failed(result) ? "ip-result bad" : "ip-result"}
          role={failed(result) ? "alert" : "status"}
        >
          <p>
            <strong>{failed(result) ? t("drive.ip.failed") : t("drive.ip.completed")}</strong>
          </p>
          <p>{result.message}</p>
          <dl className="drive-facts">
            <div>
              <dt>{t("drive.ip.maxLag")}</dt>
              <dd className="num">
                {formatInc(result.max_lag_inc)}
                <span className="muted small block">{formatRev(result.max_lag_rev)}</span>
              </dd>
            </div>
            <div>
              <dt>{t("drive.ip.finalError")}</dt>
              <dd className="num">{formatInc(result.final_error_inc)}</dd>
            </div>
            <div>
              <dt>{t("drive.ip.syncJitter")}</dt>
              <dd className="num" data-testid="sync-jitter">
                {formatMs(result.sync_jitter_ms)}
              </dd>
            </div>
            <div>
              <dt>{t("drive.ip.longestSync")}</dt>
              <dd className="num">{formatMs(result.sync_interval_max_ms)}</dd>
            </div>
            <div>
              <dt>{t("drive.ip.setPoints")}</dt>
              <dd className="num">
                {result.points} / {result.syncs}
              </dd>
            </div>
          </dl>
          {result.fault && (
            <p className="error-text">
              {t("drive.controls.fault", { code: result.fault.code_hex })}
              {result.fault.name ? ` · ${result.fault.name}` : ""}
            </p>
          )}
        </div>
      )}
    </div>
  );
}

function failed(result: IpStreamResult): boolean {
  return result.stalled || result.fault !== null;
}
