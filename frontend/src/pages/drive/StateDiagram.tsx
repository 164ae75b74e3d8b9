import type { ReactNode } from "react";

import {
  ARROWS,
  DIAGRAM,
  polylinePath,
  STATE_BOXES,
  STATE_LABELS,
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
  const from = t.from === "start" ? "Start" : t.from === "any" ? "any state" : STATE_LABELS[t.from];
  const how = t.command ? t.command.replace(/_/g, " ") : "by the drive";
  return `Transition ${number}: ${from} → ${STATE_LABELS[t.to]} (${how})`;
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
  const last = transitionNumber(lastTransition);
  const { width, height, boxWidth, boxHeight } = DIAGRAM;
  const label = state
    ? `CiA 402 state diagram: ${STATE_LABELS[state]}${last !== null ? `, after transition ${last}` : ""}`
    : "CiA 402 state diagram";
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
        Start
      </text>
      <text x={STATE_BOXES.fault.x + boxWidth / 2 - 62} y={11} className="sd-note">
        Fault (any state)
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
              {STATE_LABELS[name]}
            </text>
          </g>
        );
      })}
    </svg>
  );
}
