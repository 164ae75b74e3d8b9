import type { ReactNode } from "react";
import { Link } from "react-router";

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
    if (!Number.isFinite(speed) || speed <= 0) return { invalid: "The speed must be above 0 rpm." };
    return { body: { speed_rpm: speed } };
  }
  if (key === "test_move") {
    const distance = Number(settings.distanceRev);
    if (!Number.isFinite(distance) || distance === 0 || Math.abs(distance) > MAX_DISTANCE_REV) {
      return {
        invalid: `The distance must be between −${MAX_DISTANCE_REV} and ${MAX_DISTANCE_REV} rev, not 0.`,
      };
    }
    return { body: { distance } };
  }
  if (key === "homing") {
    return { body: settings.homingMethod === "" ? {} : { method: Number(settings.homingMethod) } };
  }
  if (key === "pdo") return { body: settings.applyPdo ? { apply: true } : {} };
  return { body: {} };
}

const MOVES: Partial<Record<StepKey, string>> = {
  stop_test:
    "ServoDesk jogs it toward the farther end of travel, quick-stops it, then jogs it back and lets the keep-alive lapse.",
  test_move: "ServoDesk jogs it for a second in each chosen mode, then makes a relative PP move.",
  homing: "ServoDesk enables the drive and runs its homing until the drive reports home attained.",
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
  return (
    <div className="run-inputs">
      <label className="inline">
        <input
          type="checkbox"
          checked={settings.applyPdo && mayConfigure}
          disabled={disabled || !mayConfigure}
          onChange={(e) => onChange({ ...settings, applyPdo: e.target.checked })}
        />{" "}
        Apply the manuals&apos; recommended mapping for the record&apos;s modes first
      </label>{" "}
      <span className="muted small">
        {mayConfigure
          ? "(writes the PDOs; without it the step checks the mapping as it is)"
          : "(writing PDOs needs the engineer role: the step checks the mapping as it is)"}
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
  return (
    <div className="run-inputs">
      <p className="warning" role="note" aria-label="The axis will move">
        <strong>The axis will move.</strong> {MOVES[stepKey] ?? ""} Keep clear of the machine.
        Anyone can stop it with the quick stop on the{" "}
        <Link to={nodeUrl(node, "drive")}>Drive page</Link> (or Quick stop all on the Network page).
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
          Speed{" "}
          <input
            className="narrow"
            type="number"
            min={1}
            step={10}
            value={settings.speedRpm}
            disabled={disabled}
            aria-label="Stop test speed (rpm)"
            onChange={(e) => onChange({ ...settings, speedRpm: e.target.value })}
          />{" "}
          rpm <span className="muted small">(at most half the speed limit)</span>
        </label>
      ) : (
        <label className="inline">
          PP move{" "}
          <input
            className="narrow"
            type="number"
            step={0.1}
            min={-MAX_DISTANCE_REV}
            max={MAX_DISTANCE_REV}
            value={settings.distanceRev}
            disabled={disabled}
            aria-label="Test move distance (rev)"
            onChange={(e) => onChange({ ...settings, distanceRev: e.target.value })}
          />{" "}
          rev <span className="muted small">(relative, at 120 rpm)</span>
        </label>
      )}
    </div>
  );
}
