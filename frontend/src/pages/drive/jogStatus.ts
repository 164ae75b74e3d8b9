// What the jog area says about the axis. The hold's own phase says what the page asked for; the
// server's jog (running → stopping → stopped) and the drive's velocity say what the axis does.
// The page never says "Stopped" while the axis moves: a released torque jog, or a stop on a
// slow ramp, reads "Stopping" until the speed is at rest.
import type { HoldPhase } from "./holdToRun";
import type { JogInfo } from "./types";

/** Below this the axis counts as at rest (the server's jog_rest_rpm). */
export const REST_RPM = 5;

/** Stops the user made: not worth repeating on the page. */
const PLAIN_STOPS = new Set(["stopped by the user", "replaced by a new jog"]);

export interface JogStatus {
  text: string;
  /** The axis is still moving after the stop (the page shows it as a warning). */
  stopping: boolean;
  /** Why the last jog of this node ended, where the user did not end it themselves. */
  reason: string | null;
}

/** The limit inputs of 60FDh (the server's `inputs` keys) as the page names them. */
const LIMIT_SWITCHES: readonly (readonly [string, string])[] = [
  ["positive_limit", "positive limit switch (P-OT)"],
  ["negative_limit", "negative limit switch (N-OT)"],
];

/** A running jog at rest on an active limit input: a drive whose limit inputs are drive
 * inhibits (MDi-S1-C) holds the axis there without a fault, so the hold alone would still
 * read "Moving". */
export function jogStatus(
  phase: HoldPhase | undefined,
  velocityRpm: number | null | undefined,
  last: JogInfo | null,
  inputs: Readonly<Record<string, boolean>> = {},
): JogStatus {
  if (phase === "running") {
    const limit = LIMIT_SWITCHES.find(([key]) => inputs[key] === true);
    if (limit && Math.abs(velocityRpm ?? 0) < REST_RPM) {
      const text = `Held at the ${limit[1]}: the drive refuses this direction — release, then jog the other way`;
      return { text, stopping: false, reason: null };
    }
    return { text: "Moving — release to stop", stopping: false, reason: null };
  }
  if (phase === "starting") return { text: "Starting…", stopping: false, reason: null };
  const why = last?.stop_reason ?? null;
  const reason = why !== null && !PLAIN_STOPS.has(why) ? why : null;
  const moving = Math.abs(velocityRpm ?? 0) >= REST_RPM;
  if (moving || last?.state === "stopping") {
    return { text: "Stopping — the axis is still moving", stopping: true, reason };
  }
  return { text: "Stopped", stopping: false, reason };
}
