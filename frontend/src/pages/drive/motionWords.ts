// What the Drive page says about motion, from the drive state (pure): the last PP move, where
// the travel ends, and ServoDesk's travel limits proposed inside the limit switches.
import { STATE_LABELS } from "./stateMachine";
import type { DriveState, MotionLimits, TravelEnds } from "./types";
import { formatInc, formatRev } from "./units";

export type MoveTone = "busy" | "ok" | "bad" | "warn";

/** The last PP move in words. A "moving" move on a drive that is not in Operation enabled
 * (an answer from before a stop) is shown as stopped: nothing moves outside that state. */
export function moveText(drive: DriveState): { text: string; tone: MoveTone } | null {
  const move = drive.move;
  if (!move) return null;
  const target = `Move to ${formatInc(move.target_inc)}`;
  const queued = move.queued > 0 ? ` · ${move.queued} queued` : "";
  switch (move.phase) {
    case "reached":
      return { text: `${target}: reached${queued}`, tone: "ok" };
    case "error":
      return { text: `${target}: error — ${move.message ?? "following error"}`, tone: "bad" };
    case "interrupted":
      return {
        text: `${target}: not reached — ${move.message ?? "stopped before its target"}`,
        tone: "warn",
      };
    case "moving":
      if (drive.state !== "operation_enabled") {
        return {
          text: `${target}: not reached — stopped: the drive is ${STATE_LABELS[drive.state]}`,
          tone: "warn",
        };
      }
      return { text: `${target}: moving${queued}`, tone: "busy" };
  }
}

/** "−5.000 rev … 5.000 rev" (kept on one line), an open side as "no end". */
export function rangeText(min: number | null | undefined, max: number | null | undefined): string {
  const end = (value: number | null | undefined) => (value == null ? "no end" : formatRev(value));
  return `${end(min)} … ${end(max)}`.replace(/ /g, "\u00a0");
}

export interface TravelRow {
  key: "switches" | "software_limit" | "servodesk";
  label: string;
  range: string;
  source: string;
  note: string;
}

/** Where the travel ends, one row per thing that ends it. */
export function travelRows(drive: DriveState): TravelRow[] {
  const rows: TravelRow[] = [];
  const travel = drive.travel;
  const row = (key: TravelRow["key"], label: string, ends: TravelEnds): TravelRow => ({
    key,
    label,
    range: rangeText(ends.min_rev, ends.max_rev),
    source: ends.source,
    note: ends.note,
  });
  if (travel?.switches) {
    rows.push(row("switches", "Limit switches", travel.switches));
  }
  if (travel?.software_limit) {
    rows.push(row("software_limit", "Drive's software limit", travel.software_limit));
  }
  const { min_position_rev: min, max_position_rev: max } = drive.limits;
  const none = min == null && max == null;
  rows.push({
    key: "servodesk",
    label: "ServoDesk's travel limits",
    range: none ? "none" : rangeText(min, max),
    source: "ServoDesk",
    note: none
      ? "PP moves are not checked against a travel range"
      : "PP moves beyond these are refused before anything is sent",
  });
  return rows;
}

/** How far inside the limit switches the proposed travel limits stay. */
export const SWITCH_MARGIN_REV = 0.1;

/** ServoDesk's travel limits just inside the limit switches (or the drive's software limit),
 * keeping the speed and torque limits in force; null when nothing ends the travel. */
export function limitsInsideSwitches(drive: DriveState): MotionLimits | null {
  const ends = drive.travel?.switches ?? drive.travel?.software_limit;
  if (!ends || (ends.min_rev == null && ends.max_rev == null)) return null;
  const margin = drive.travel?.switches ? SWITCH_MARGIN_REV : 0;
  const round = (value: number) => Math.round(value * 1000) / 1000;
  const min = ends.min_rev == null ? null : round(ends.min_rev + margin);
  const max = ends.max_rev == null ? null : round(ends.max_rev - margin);
  if (min !== null && max !== null && min >= max) return null;
  return { ...drive.limits, min_position_rev: min, max_position_rev: max };
}
