import { useState, type ReactNode } from "react";

import { move, moveQueue } from "../../api/driveApi";
import { ErrorText } from "../../components/ErrorText";
import { i18n, useTranslation } from "../../i18n";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";
import { moveText } from "./motionWords";
import type { DriveState, MoveRequest } from "./types";
import { checkRange, formatRev } from "./units";

function describeMove(m: MoveRequest): string {
  const words = { position: formatRev(m.position_rev), rpm: m.velocity_rpm };
  return m.relative ? i18n.t("drive.pp.by", words) : i18n.t("drive.pp.to", words);
}

/** Profile position: step ±, go to a position (absolute or relative), and a queued sequence. */
export function PpJog({
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
  const [position, setPosition] = useState("1");
  const [relative, setRelative] = useState(true);
  const [velocity, setVelocity] = useState("120");
  const [acceleration, setAcceleration] = useState("600");
  const [immediately, setImmediately] = useState(false);
  const [queue, setQueue] = useState<MoveRequest[]>([]);
  const go = useAction(async (request: MoveRequest) => show(await move(node, request)));
  const runQueue = useAction(async () => {
    show(await moveQueue(node, queue));
    setQueue([]);
  });

  const pos = checkRange(position, {});
  const vel = checkRange(velocity, { positive: true, max: drive.limits.max_velocity_rpm });
  const acc = checkRange(acceleration, { positive: true });
  const valid = pos.value !== null && vel.value !== null && acc.value !== null;
  const enabled = drive.state === "operation_enabled";
  const allowed = valid && enabled && mayCommand && !go.busy;
  const operate = useMay("operate");
  const moveGate = operate.gate(t("drive.pp.gate"), { disabled: !allowed });

  const request = (positionRev: number, rel: boolean): MoveRequest => ({
    mode: "pp",
    position_rev: positionRev,
    relative: rel,
    velocity_rpm: vel.value ?? 0,
    acceleration_rpm_s: acc.value ?? undefined,
    immediately,
  });
  const step = Math.abs(pos.value ?? 0);
  const moved = moveText(drive);

  return (
    <div className="pp-jog">
      <div className="drive-form">
        <label>
          <span>{t("drive.pp.position")}</span>
          <input
            className="narrow"
            inputMode="decimal"
            aria-invalid={pos.error !== null}
            value={position}
            onChange={(e) => setPosition(e.target.value)}
          />
        </label>
        <label className="check">
          <input
            type="checkbox"
            checked={relative}
            onChange={(e) => setRelative(e.target.checked)}
          />
          {t("drive.pp.relative")}
        </label>
        <label>
          <span>{t("drive.pp.velocity")}</span>
          <input
            className="narrow"
            inputMode="decimal"
            aria-invalid={vel.error !== null}
            title={vel.error ?? undefined}
            value={velocity}
            onChange={(e) => setVelocity(e.target.value)}
          />
        </label>
        <label>
          <span>{t("drive.hold.acceleration")}</span>
          <input
            className="narrow"
            inputMode="decimal"
            aria-invalid={acc.error !== null}
            value={acceleration}
            onChange={(e) => setAcceleration(e.target.value)}
          />
        </label>
        <label className="check">
          <input
            type="checkbox"
            checked={immediately}
            onChange={(e) => setImmediately(e.target.checked)}
          />
          {t("drive.pp.immediately")}
        </label>
      </div>
      <div className="button-row">
        <button type="button" {...moveGate} onClick={() => void go.run(request(-step, true))}>
          {t("drive.pp.stepBack", { step })}
        </button>
        <button type="button" {...moveGate} onClick={() => void go.run(request(step, true))}>
          {t("drive.pp.stepForward", { step })}
        </button>
        <button
          type="button"
          className="primary"
          {...moveGate}
          onClick={() => void go.run(request(pos.value ?? 0, relative))}
        >
          {relative
            ? t("drive.pp.moveBy", { position: formatRev(pos.value) })
            : t("drive.pp.goTo", { position: formatRev(pos.value) })}
        </button>
        <button
          type="button"
          disabled={!valid || queue.length >= 64}
          onClick={() => setQueue([...queue, request(pos.value ?? 0, relative)])}
        >
          {t("drive.pp.add")}
        </button>
        <ErrorText error={go.error} inline />
      </div>
      {!enabled && <p className="muted small">{t("drive.pp.enableToMove")}</p>}
      {moved && (
        <p className={`small move-${moved.tone}`} role="status" data-testid="pp-move">
          {moved.text}
        </p>
      )}
      {queue.length > 0 && (
        <div className="pp-queue">
          <ol aria-label={t("drive.pp.sequence")}>
            {queue.map((m, i) => (
              <li key={i}>
                {describeMove(m)}
                <button
                  type="button"
                  className="link-button small"
                  aria-label={t("drive.pp.removeLabel", { number: i + 1 })}
                  onClick={() => setQueue(queue.filter((_, j) => j !== i))}
                >
                  {t("drive.pp.remove")}
                </button>
              </li>
            ))}
          </ol>
          <div className="button-row">
            <button
              type="button"
              className="primary"
              {...operate.gate(t("drive.pp.gate"), {
                disabled: !enabled || !mayCommand || runQueue.busy,
              })}
              onClick={() => void runQueue.run()}
            >
              {t("drive.pp.runSequence", { count: queue.length })}
            </button>
            <button type="button" onClick={() => setQueue([])}>
              {t("drive.pp.clear")}
            </button>
            <ErrorText error={runQueue.error} inline />
          </div>
        </div>
      )}
    </div>
  );
}
