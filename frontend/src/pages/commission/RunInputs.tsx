import type { ReactNode } from "react";
import { Link } from "react-router";

import { nodeUrl } from "../../nav/routes";
import { DEFAULT_DISTANCE_REV, DEFAULT_SPEED_RPM, MAX_DISTANCE_REV } from "./steps";
import type { StepKey } from "./types";

export interface RunSettings {
  speedRpm: string;
  distanceRev: string;
}

export const DEFAULT_RUN_SETTINGS: RunSettings = {
  speedRpm: String(DEFAULT_SPEED_RPM),
  distanceRev: String(DEFAULT_DISTANCE_REV),
};

/** The run's body from the inputs, or the reason it cannot be sent. */
export function runBody(
  key: StepKey,
  settings: RunSettings,
): { body: { speed_rpm?: number; distance?: number } } | { invalid: string } {
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
  return { body: {} };
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
        <strong>The axis will move.</strong>{" "}
        {stepKey === "stop_test"
          ? "ServoDesk jogs it toward the farther end of travel, quick-stops it, then jogs it back and lets the keep-alive lapse."
          : "ServoDesk jogs it for a second in each chosen mode, then makes a relative PP move."}{" "}
        Keep clear of the machine. Anyone can stop it with the quick stop on the{" "}
        <Link to={nodeUrl(node, "drive")}>Drive page</Link> (or Quick stop all on the Network page).
      </p>
      {stepKey === "stop_test" ? (
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
