import type { ReactNode } from "react";

import { currentLocale, i18n, useTranslation } from "../../i18n";
import {
  ARROWS,
  commandLabel,
  DIAGRAM,
  polylinePath,
  STATE_BOXES,
  stateLabel,
  TRANSITIONS,
  transitionNumber,
} from "./stateMachine";
import type { DriveStateName } from "./types";

const STATES = Object.keys(STATE_BOXES) as DriveStateName[];

/** Power-off states left, power-on states right in the manual's figure; here the states that
 * can move the axis are tinted so "where is torque on" reads at a glance. */
const POWERED: ReadonlySet<DriveStateName> = new Set(["operation_enabled", "quick_stop_active"]);

function transitionTitle(number: number): string {
  const t = TRANSITIONS.find((x) => x.number === number);
  if (!t) return String(number);
  const from =
    t.from === "start"
      ? i18n.t("drive.diagram.start")
      : t.from === "any"
        ? i18n.t("drive.diagram.anyState")
        : stateLabel(t.from);
  // the command as a word in the sentence: "shutdown", "switch on" (a no-op for Chinese)
  const how = t.command
    ? commandLabel(t.command).toLocaleLowerCase(currentLocale())
    : i18n.t("drive.diagram.byDrive");
  return i18n.t("drive.diagram.transition", { number, from, to: stateLabel(t.to), how });
}

/** The CiA 402 state machine (MDi-S1-C CANopen manual §3.2.1) with the drive's state and the
 * transition it just took highlighted. */
export function StateDiagram({
  state,
  lastTransition,
}: {
  state: DriveStateName | null;
  lastTransition: string | null;
}): ReactNode {
  const { t } = useTranslation();
  const last = transitionNumber(lastTransition);
  const { width, height, boxWidth, boxHeight } = DIAGRAM;
  const label = !state
    ? t("drive.diagram.label")
    : last !== null
      ? t("drive.diagram.labelAfter", { state: stateLabel(state), number: last })
      : t("drive.diagram.labelState", { state: stateLabel(state) });
  return (
    <svg
      className="state-diagram"
      viewBox={`0 0 ${width} ${height}`}
      role="img"
      aria-label={label}
      data-testid="state-diagram"
    >
      <defs>
        <marker
          id="sd-head"
          viewBox="0 0 10 10"
          refX="9"
          refY="5"
          markerUnits="userSpaceOnUse"
          markerWidth="9"
          markerHeight="9"
          orient="auto-start-reverse"
        >
          <path d="M0 0 L10 5 L0 10 z" className="sd-head" />
        </marker>
        <marker
          id="sd-head-active"
          viewBox="0 0 10 10"
          refX="9"
          refY="5"
          markerUnits="userSpaceOnUse"
          markerWidth="9"
          markerHeight="9"
          orient="auto-start-reverse"
        >
          <path d="M0 0 L10 5 L0 10 z" className="sd-head active" />
        </marker>
      </defs>
      <text x={STATE_BOXES.not_ready_to_switch_on.x + boxWidth / 2 - 40} y={11} className="sd-note">
        {t("drive.diagram.start")}
      </text>
      <text x={STATE_BOXES.fault.x + boxWidth / 2 - 62} y={11} className="sd-note">
        {t("drive.diagram.faultAny")}
      </text>
      {ARROWS.map((arrow) => {
        const active = arrow.number === last;
        return (
          <g
            key={arrow.number}
            className={active ? "sd-arrow active" : "sd-arrow"}
            data-transition={arrow.number}
          >
            <title>{transitionTitle(arrow.number)}</title>
            <path
              d={polylinePath(arrow.points)}
              markerEnd={`url(#${active ? "sd-head-active" : "sd-head"})`}
            />
            <text x={arrow.label[0]} y={arrow.label[1]} className="sd-number">
              {arrow.number}
            </text>
          </g>
        );
      })}
      {STATES.map((name) => {
        const box = STATE_BOXES[name];
        const current = name === state;
        const classes = ["sd-state"];
        if (current) classes.push("current");
        if (POWERED.has(name)) classes.push("powered");
        if (name === "fault" || name === "fault_reaction_active") classes.push("faulty");
        return (
          <g key={name} className={classes.join(" ")} data-state={name}>
            <rect x={box.x} y={box.y} width={boxWidth} height={boxHeight} rx={6} />
            <text x={box.x + boxWidth / 2} y={box.y + boxHeight / 2 + 5} textAnchor="middle">
              {stateLabel(name)}
            </text>
          </g>
        );
      })}
    </svg>
  );
}
