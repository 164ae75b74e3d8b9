// What the jog area says about the axis. The hold's own phase says what the page asked for; the
// server's jog (running → stopping → stopped) and the drive's velocity say what the axis does.
// The page never says "Stopped" while the axis moves: a released torque jog, or a stop on a
// slow ramp, reads "Stopping" until the speed is at rest.
import { i18n, type MessageKey } from "../../i18n";
import { serverText } from "../../lib/serverText";
import type { HoldPhase } from "./holdToRun";
import type { JogInfo } from "./types";

/** Below this the axis counts as at rest (the server's jog_rest_rpm). */
export const REST_RPM = 5;

/** Stops the user made (by the reason's id; its English for an older server): not worth
 * repeating on the page. */
const PLAIN_STOPS = new Set([
  "stop.user",
  "stop.replaced",
  "stopped by the user",
  "replaced by a new jog",
]);

export interface JogStatus {
  text: string;
  /** The axis is still moving after the stop (the page shows it as a warning). */
  stopping: boolean;
  /** Why the last jog of this node ended, where the user did not end it themselves. */
  reason: string | null;
}

/** The limit inputs of 60FDh (the server's `inputs` keys) as the page names them. */
const LIMIT_SWITCHES: readonly (readonly [string, MessageKey])[] = [
  ["positive_limit", "drive.hold.positiveLimit"],
  ["negative_limit", "drive.hold.negativeLimit"],
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
      const text = i18n.t("drive.hold.heldAt", { limit: i18n.t(limit[1]) });
      return { text, stopping: false, reason: null };
    }
    return { text: i18n.t("drive.hold.moving"), stopping: false, reason: null };
  }
  if (phase === "starting")
    return { text: i18n.t("drive.hold.starting"), stopping: false, reason: null };
  const why = last?.stop_reason ?? null;
  const plain = PLAIN_STOPS.has(last?.stop_reason_id ?? why ?? "");
  const reason =
    why !== null && !plain
      ? serverText({
          message: why,
          message_id: last?.stop_reason_id,
          params: last?.stop_reason_params,
        })
      : null;
  const moving = Math.abs(velocityRpm ?? 0) >= REST_RPM;
  if (moving || last?.state === "stopping") {
    return { text: i18n.t("drive.hold.stopping"), stopping: true, reason };
  }
  return { text: i18n.t("drive.hold.stopped"), stopping: false, reason };
}
