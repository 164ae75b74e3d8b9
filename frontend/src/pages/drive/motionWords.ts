// What the Drive page says about motion, from the drive state (pure): the last PP move, where
// the travel ends, and ServoDesk's travel limits proposed inside the limit switches.
import { currentLanguage, i18n } from "../../i18n";
import { stateLabel } from "./stateMachine";
import type { DriveState, MotionLimits, TravelEnds } from "./types";
import { formatInc, formatRev } from "./units";

export type MoveTone = "busy" | "ok" | "bad" | "warn";

/** The last PP move in words. A "moving" move on a drive that is not in Operation enabled
 * (an answer from before a stop) is shown as stopped: nothing moves outside that state. */
export function moveText(drive: DriveState): { text: string; tone: MoveTone } | null {
  const move = drive.move;
  if (!move) return null;
  const target = formatInc(move.target_inc);
  const count = move.queued;
  switch (move.phase) {
    case "reached":
      return {
        text:
          count > 0
            ? i18n.t("drive.move.reachedQueued", { target, count })
            : i18n.t("drive.move.reached", { target }),
        tone: "ok",
      };
    case "error":
      return {
        text: i18n.t("drive.move.error", {
          target,
          message: move.message ?? i18n.t("drive.move.followingError"),
        }),
        tone: "bad",
      };
    case "interrupted":
      return {
        text: i18n.t("drive.move.interrupted", {
          target,
          message: move.message ?? i18n.t("drive.move.stoppedBefore"),
        }),
        tone: "warn",
      };
    case "moving":
      if (drive.state !== "operation_enabled") {
        return {
          text: i18n.t("drive.move.stoppedState", { target, state: stateLabel(drive.state) }),
          tone: "warn",
        };
      }
      return {
        text:
          count > 0
            ? i18n.t("drive.move.movingQueued", { target, count })
            : i18n.t("drive.move.moving", { target }),
        tone: "busy",
      };
  }
}

/** "−5.000 rev … 5.000 rev" (kept on one line), an open side as "no end". */
export function rangeText(min: number | null | undefined, max: number | null | undefined): string {
  const end = (value: number | null | undefined) =>
    value == null ? i18n.t("drive.travel.noEnd") : formatRev(value);
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
  // the server's source and note are fixed words for these two (servodesk.motion.axis
  // travel_info): the page says them in its own language
  if (travel?.switches) {
    rows.push({
      ...row("switches", i18n.t("drive.travel.switches"), travel.switches),
      source: i18n.t("drive.travel.switchesSource"),
      note: i18n.t("drive.travel.switchesNote"),
    });
  }
  if (travel?.software_limit) {
    const ends = travel.software_limit;
    rows.push({
      ...row("software_limit", i18n.t("drive.travel.softwareLimit"), ends),
      source: i18n.t("drive.travel.softwareLimitSource"),
      note: ends.note ? i18n.t("drive.travel.softwareLimitOff") : "",
    });
  }
  const { min_position_rev: min, max_position_rev: max } = drive.limits;
  const none = min == null && max == null;
  rows.push({
    key: "servodesk",
    label: i18n.t("drive.travel.servodesk"),
    range: none ? i18n.t("drive.travel.none") : rangeText(min, max),
    source: "ServoDesk",
    note: none ? i18n.t("drive.travel.unchecked") : i18n.t("drive.travel.refused"),
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

type DriveFault = NonNullable<DriveState["fault"]>;

/** The drive's active fault (603Fh decoded) in the page's language: in Chinese the table's
 * Chinese where it has it (the MDi-S1-C manual's own, else ServoDesk's translation). */
export function faultInWords(
  fault: DriveFault,
): Pick<DriveFault, "code_hex" | "name" | "text" | "source"> {
  if (currentLanguage() !== "zh-CN") return fault;
  return {
    code_hex: fault.code_hex,
    name: fault.name_zh ?? fault.name,
    text: fault.text_zh ?? fault.text,
    source: fault.source_zh ?? fault.source,
  };
}
