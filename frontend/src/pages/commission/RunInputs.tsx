import type { ReactNode } from "react";
import { Link } from "react-router";

import { i18n, Trans, useTranslation, type MessageKey } from "../../i18n";
import { nodeUrl } from "../../nav/paths";
import { HomingMethodInput } from "./HomingMethodInput";
import { DEFAULT_DISTANCE_REV, DEFAULT_SPEED_RPM, MAX_DISTANCE_REV } from "./steps";
import type { StepKey, StepRun } from "./types";

export interface RunSettings {
  speedRpm: string;
  distanceRev: string;
  /** homing: a method number, or "" for the one the drive is set to (6098h) */
  homingMethod: string;
  /** pdo: apply the manuals' recommended mapping for the record's modes first */
  applyPdo: boolean;
}

export const DEFAULT_RUN_SETTINGS: RunSettings = {
  speedRpm: String(DEFAULT_SPEED_RPM),
  distanceRev: String(DEFAULT_DISTANCE_REV),
  homingMethod: "",
  applyPdo: false,
};

export type RunBody = StepRun;

/** The run's body from the inputs, or the reason it cannot be sent. */
export function runBody(
  key: StepKey,
  settings: RunSettings,
): { body: RunBody } | { invalid: string } {
  if (key === "stop_test") {
    const speed = Number(settings.speedRpm);
    if (!Number.isFinite(speed) || speed <= 0)
      return { invalid: i18n.t("commission.run.badSpeed") };
    return { body: { speed_rpm: speed } };
  }
  if (key === "test_move") {
    const distance = Number(settings.distanceRev);
    if (!Number.isFinite(distance) || distance === 0 || Math.abs(distance) > MAX_DISTANCE_REV) {
      return { invalid: i18n.t("commission.run.badDistance", { max: MAX_DISTANCE_REV }) };
    }
    return { body: { distance } };
  }
  if (key === "homing") {
    return { body: settings.homingMethod === "" ? {} : { method: Number(settings.homingMethod) } };
  }
  if (key === "pdo") return { body: settings.applyPdo ? { apply: true } : {} };
  return { body: {} };
}

const MOVES: Partial<Record<StepKey, MessageKey>> = {
  stop_test: "commission.run.moves.stop_test",
  test_move: "commission.run.moves.test_move",
  homing: "commission.run.moves.homing",
};

/** The pdo step's choice: check the mapping as it is, or apply the recommended one first. */
export function PdoRunInput({
  settings,
  onChange,
  disabled,
  mayConfigure,
}: {
  settings: RunSettings;
  onChange: (settings: RunSettings) => void;
  disabled: boolean;
  mayConfigure: boolean;
}): ReactNode {
  const { t } = useTranslation();
  return (
    <div className="run-inputs">
      <label className="inline">
        <input
          type="checkbox"
          checked={settings.applyPdo && mayConfigure}
          disabled={disabled || !mayConfigure}
          onChange={(e) => onChange({ ...settings, applyPdo: e.target.checked })}
        />{" "}
        {t("commission.run.applyPdo")}
      </label>{" "}
      <span className="muted small">
        {mayConfigure
          ? t("commission.run.applyPdoWrites")
          : t("commission.run.applyPdoNeedsEngineer")}
      </span>
    </div>
  );
}

/** The moving steps' inputs, with the warning that the axis moves and who may stop it. */
export function RunInputs({
  node,
  stepKey,
  settings,
  onChange,
  disabled,
}: {
  node: number;
  stepKey: StepKey;
  settings: RunSettings;
  onChange: (settings: RunSettings) => void;
  disabled: boolean;
}): ReactNode {
  const { t } = useTranslation();
  const moves = MOVES[stepKey];
  return (
    <div className="run-inputs">
      <p className="warning" role="note" aria-label={t("commission.run.moveLabel")}>
        <Trans
          i18nKey="commission.run.warning"
          values={{ moves: moves ? t(moves) : "" }}
          components={{ strong: <strong />, page: <Link to={nodeUrl(node, "drive")} /> }}
        />
      </p>
      {stepKey === "homing" ? (
        <HomingMethodInput
          node={node}
          value={settings.homingMethod}
          disabled={disabled}
          onChange={(homingMethod) => onChange({ ...settings, homingMethod })}
        />
      ) : stepKey === "stop_test" ? (
        <label className="inline">
          {t("commission.run.speed")}{" "}
          <input
            className="narrow"
            type="number"
            min={1}
            step={10}
            value={settings.speedRpm}
            disabled={disabled}
            aria-label={t("commission.run.speedLabel")}
            onChange={(e) => onChange({ ...settings, speedRpm: e.target.value })}
          />{" "}
          rpm <span className="muted small">{t("commission.run.speedHint")}</span>
        </label>
      ) : (
        <label className="inline">
          {t("commission.run.ppMove")}{" "}
          <input
            className="narrow"
            type="number"
            step={0.1}
            min={-MAX_DISTANCE_REV}
            max={MAX_DISTANCE_REV}
            value={settings.distanceRev}
            disabled={disabled}
            aria-label={t("commission.run.distanceLabel")}
            onChange={(e) => onChange({ ...settings, distanceRev: e.target.value })}
          />{" "}
          rev <span className="muted small">{t("commission.run.distanceHint")}</span>
        </label>
      )}
    </div>
  );
}
