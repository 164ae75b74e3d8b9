// A homing method's path as a small drawing (after the figures of MDi-S1-C CANopen manual
// §3.7.3): the axis with its switches, one arrow per step, each step a row lower than the one
// before, fast steps bold, slow ones thin, a reversal drawn as a bend between rows. Pure
// geometry from the server's `path`; the component only turns it into SVG.
import { i18n } from "../../i18n";
import { untilWords } from "./homingWords";
import type { PathStep } from "./types";

export type SwitchName = "negative_limit" | "home" | "positive_limit";

export interface SwitchZone {
  name: SwitchName;
  label: string;
  x0: number;
  x1: number;
}

export interface StepArrow {
  index: number;
  x0: number;
  x1: number;
  y: number;
  speed: PathStep["speed"];
  direction: PathStep["direction"];
  until: string;
  /** The bend joining it to the previous step (a reversal or a change of speed). */
  join: { x: number; y0: number; y1: number; reversal: boolean } | null;
}

export interface HomingDrawing {
  width: number;
  height: number;
  axisY: number;
  switches: SwitchZone[];
  start: number;
  arrows: StepArrow[];
  /** Where the axis ends up (the home position), x. */
  end: number;
  /** How the "home" label is anchored at `end` so it clears the switch's own label. */
  homeAnchor: "start" | "middle" | "end";
}

export const HOMING_GEOMETRY = {
  width: 260,
  left: 14,
  right: 246,
  rowTop: 20,
  rowHeight: 22,
  limitWidth: 44,
  homeWidth: 54,
  overshoot: 26,
  axisGap: 14,
} as const;

const G = HOMING_GEOMETRY;

const LABELS: Readonly<Record<SwitchName, string>> = {
  negative_limit: "N-OT",
  home: "HW",
  positive_limit: "P-OT",
};

/** Which switch a step's `until` names ("negative limit switch rises" → negative_limit). */
export function switchOf(until: string): SwitchName | null {
  const text = until.toLowerCase();
  if (/neg\w*\s+limit|n-ot|negative end/.test(text)) return "negative_limit";
  if (/pos\w*\s+limit|p-ot|positive end/.test(text)) return "positive_limit";
  if (/home|hw\b|reference|origin/.test(text)) return "home";
  if (/\blimit\b/.test(text)) return null;
  return null;
}

/** Whether the step ends on the switch's rising edge (arriving) or falling edge (leaving). */
export function edgeOf(until: string): "rise" | "fall" {
  return /fall|leav|release|off\b|low|clear/.test(until.toLowerCase()) ? "fall" : "rise";
}

function zone(name: SwitchName): SwitchZone {
  const center = (G.left + G.right) / 2;
  switch (name) {
    case "negative_limit":
      return { name, label: LABELS[name], x0: G.left, x1: G.left + G.limitWidth };
    case "positive_limit":
      return { name, label: LABELS[name], x0: G.right - G.limitWidth, x1: G.right };
    case "home":
      return {
        name,
        label: LABELS[name],
        x0: center - G.homeWidth / 2,
        x1: center + G.homeWidth / 2,
      };
  }
}

/** The switches the path mentions, negative to positive; the limits are drawn whenever the
 * home switch is, because a method may reverse on them. */
function switchesFor(steps: readonly PathStep[]): SwitchZone[] {
  const named = new Set(steps.map((s) => switchOf(s.until)).filter((n) => n !== null));
  const order: SwitchName[] = ["negative_limit", "home", "positive_limit"];
  return order.filter((n) => named.has(n)).map(zone);
}

/** Where the axis starts: between the first target and the other switches, far enough away
 * for the first arrow to show its direction. */
function startX(steps: readonly PathStep[], switches: readonly SwitchZone[]): number {
  const first = steps[0];
  const center = (G.left + G.right) / 2;
  if (!first) return center;
  const target = switches.find((s) => s.name === switchOf(first.until));
  const home = switches.find((s) => s.name === "home");
  const positive = first.direction === "positive";
  if (target?.name === "home" || (!target && home)) {
    return positive ? (G.left + (home?.x0 ?? center)) / 2 : ((home?.x1 ?? center) + G.right) / 2;
  }
  if (home) {
    // heading for a limit with the home switch behind: start between the two
    return positive
      ? (home.x1 + G.right - G.limitWidth) / 2
      : (G.left + G.limitWidth + home.x0) / 2;
  }
  return positive ? center - 50 : center + 50;
}

/** Where a step stops: on the edge it is looking for, past it by the deceleration for a
 * rising edge the axis then reverses from. */
function stopX(step: PathStep, from: number, switches: readonly SwitchZone[]): number {
  const sign = step.direction === "positive" ? 1 : -1;
  const target = switches.find((s) => s.name === switchOf(step.until));
  if (!target) return clamp(from + sign * 60);
  const edge = edgeOf(step.until);
  if (edge === "fall") return sign > 0 ? target.x1 : target.x0;
  const entry = sign > 0 ? target.x0 : target.x1;
  return clamp(entry + sign * G.overshoot);
}

function clamp(x: number): number {
  return Math.max(G.left, Math.min(G.right, x));
}

export function homingDrawing(steps: readonly PathStep[]): HomingDrawing {
  const switches = switchesFor(steps);
  const start = startX(steps, switches);
  const arrows: StepArrow[] = [];
  let x = start;
  steps.forEach((step, index) => {
    // each step a row lower; the bend joins it to where the previous one stopped
    const y = G.rowTop + index * G.rowHeight;
    const x1 = stopX(step, x, switches);
    const previous = steps[index - 1];
    const join = previous
      ? { x, y0: y - G.rowHeight, y1: y, reversal: previous.direction !== step.direction }
      : null;
    arrows.push({
      index,
      x0: x,
      x1,
      y,
      speed: step.speed,
      direction: step.direction,
      until: step.until,
      join,
    });
    x = x1;
  });
  const rows = Math.max(1, steps.length);
  const axisY = G.rowTop + (rows - 1) * G.rowHeight + G.axisGap + 6;
  // the home label goes beside its marker, away from the switch the marker sits on
  const on = switches.find((z) => x >= z.x0 && x <= z.x1);
  const homeAnchor: HomingDrawing["homeAnchor"] = !on
    ? "middle"
    : x >= (on.x0 + on.x1) / 2
      ? "start"
      : "end";
  return { width: G.width, height: axisY + 26, axisY, switches, start, arrows, end: x, homeAnchor };
}

/** The arrowhead triangle at (x, y) pointing in `direction`. */
export function arrowHead(x: number, y: number, direction: PathStep["direction"]): string {
  const s = direction === "positive" ? -1 : 1;
  return `${x},${y} ${x + s * 7},${y - 4} ${x + s * 7},${y + 4}`;
}

/** A step in words, for the drawing's caption and its screen-reader text. */
export function describeStep(step: PathStep): string {
  const until = untilWords(step.until);
  if (step.speed === "fast") {
    return step.direction === "positive"
      ? i18n.t("drive.homing.fastPositive", { until })
      : i18n.t("drive.homing.fastNegative", { until });
  }
  return step.direction === "positive"
    ? i18n.t("drive.homing.slowPositive", { until })
    : i18n.t("drive.homing.slowNegative", { until });
}
