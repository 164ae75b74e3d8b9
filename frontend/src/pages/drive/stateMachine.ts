// The CiA 402 device-control state machine (MDi-S1-C CANopen manual §3.2.1, figure 3.1;
// §3.2.2 figure 3.2 for the commands) as data: the eight states, the numbered transitions with
// the controlword that takes each, and the diagram's geometry. Pure: the SVG only draws this.
import { i18n, type MessageKey } from "../../i18n";
import type { DriveStateName } from "./types";

const STATE_KEYS: Readonly<Record<DriveStateName, MessageKey>> = {
  not_ready_to_switch_on: "drive.state.not_ready_to_switch_on",
  switch_on_disabled: "drive.state.switch_on_disabled",
  ready_to_switch_on: "drive.state.ready_to_switch_on",
  switched_on: "drive.state.switched_on",
  operation_enabled: "drive.state.operation_enabled",
  quick_stop_active: "drive.state.quick_stop_active",
  fault_reaction_active: "drive.state.fault_reaction_active",
  fault: "drive.state.fault",
};

/** A state's name in the current language (looked up per call: the language can change). */
export function stateLabel(state: DriveStateName): string {
  return i18n.t(STATE_KEYS[state]);
}

/** The statusword pattern of each state (CiA 402; MDi-S1-C CANopen manual §3.2.3). */
const STATE_PATTERNS: readonly { mask: number; value: number; state: DriveStateName }[] = [
  { mask: 0x4f, value: 0x00, state: "not_ready_to_switch_on" },
  { mask: 0x4f, value: 0x40, state: "switch_on_disabled" },
  { mask: 0x6f, value: 0x21, state: "ready_to_switch_on" },
  { mask: 0x6f, value: 0x23, state: "switched_on" },
  { mask: 0x6f, value: 0x27, state: "operation_enabled" },
  { mask: 0x6f, value: 0x07, state: "quick_stop_active" },
  { mask: 0x4f, value: 0x0f, state: "fault_reaction_active" },
  { mask: 0x4f, value: 0x08, state: "fault" },
];

/** The state a statusword reports; null for a pattern CiA 402 does not define. */
export function stateFromStatusword(statusword: number): DriveStateName | null {
  const found = STATE_PATTERNS.find((p) => (statusword & p.mask) === p.value);
  return found ? found.state : null;
}

export type CommandName =
  | "shutdown"
  | "switch_on"
  | "enable_operation"
  | "disable_operation"
  | "disable_voltage"
  | "quick_stop"
  | "fault_reset";

export interface Transition {
  number: number;
  from: DriveStateName | "start" | "any";
  to: DriveStateName;
  /** The controlword command that takes it; null when the drive takes it by itself. */
  command: CommandName | null;
}

export const TRANSITIONS: readonly Transition[] = [
  { number: 0, from: "start", to: "not_ready_to_switch_on", command: null },
  { number: 1, from: "not_ready_to_switch_on", to: "switch_on_disabled", command: null },
  { number: 2, from: "switch_on_disabled", to: "ready_to_switch_on", command: "shutdown" },
  { number: 3, from: "ready_to_switch_on", to: "switched_on", command: "switch_on" },
  { number: 4, from: "switched_on", to: "operation_enabled", command: "enable_operation" },
  { number: 5, from: "operation_enabled", to: "switched_on", command: "disable_operation" },
  { number: 6, from: "switched_on", to: "ready_to_switch_on", command: "shutdown" },
  { number: 7, from: "ready_to_switch_on", to: "switch_on_disabled", command: "disable_voltage" },
  { number: 8, from: "operation_enabled", to: "ready_to_switch_on", command: "shutdown" },
  { number: 9, from: "operation_enabled", to: "switch_on_disabled", command: "disable_voltage" },
  { number: 10, from: "switched_on", to: "switch_on_disabled", command: "disable_voltage" },
  { number: 11, from: "operation_enabled", to: "quick_stop_active", command: "quick_stop" },
  { number: 12, from: "quick_stop_active", to: "switch_on_disabled", command: "disable_voltage" },
  { number: 13, from: "any", to: "fault_reaction_active", command: null },
  { number: 14, from: "fault_reaction_active", to: "fault", command: null },
  { number: 15, from: "fault", to: "switch_on_disabled", command: "fault_reset" },
  { number: 16, from: "quick_stop_active", to: "operation_enabled", command: "enable_operation" },
];

export interface CommandInfo {
  name: CommandName;
  /** Its button's name, a catalogue key. */
  label: MessageKey;
  /** Controlword 6040h bits 0–3 and 7 (figure 3.2). */
  controlword: number;
}

export const COMMANDS: readonly CommandInfo[] = [
  { name: "shutdown", label: "drive.command.shutdown", controlword: 0x0006 },
  { name: "switch_on", label: "drive.command.switch_on", controlword: 0x0007 },
  { name: "enable_operation", label: "drive.command.enable_operation", controlword: 0x000f },
  { name: "disable_operation", label: "drive.command.disable_operation", controlword: 0x0007 },
  { name: "disable_voltage", label: "drive.command.disable_voltage", controlword: 0x0000 },
  { name: "quick_stop", label: "drive.command.quick_stop", controlword: 0x0002 },
  { name: "fault_reset", label: "drive.command.fault_reset", controlword: 0x0080 },
];

/** A command's name in the current language. */
export function commandLabel(name: CommandName): string {
  const info = COMMANDS.find((c) => c.name === name);
  return info ? i18n.t(info.label) : name;
}

/** The transitions a command takes from `state` (empty: the command does nothing there). */
export function transitionsFor(command: CommandName, state: DriveStateName): Transition[] {
  return TRANSITIONS.filter((t) => t.command === command && t.from === state);
}

/** "enable operation (4)" → 4; a bare number also works; null when none is named. */
export function transitionNumber(text: string | null | undefined): number | null {
  if (!text) return null;
  const match = /\((\d{1,2})\)\s*$/.exec(text) ?? /^\s*(\d{1,2})\s*$/.exec(text);
  if (!match?.[1]) return null;
  const number = Number(match[1]);
  return number <= 16 ? number : null;
}

/** The path of transitions the Enable button asks for, from the state the drive is in. */
export function enablePath(state: DriveStateName): number[] {
  switch (state) {
    case "switch_on_disabled":
      return [2, 3, 4];
    case "ready_to_switch_on":
      return [3, 4];
    case "switched_on":
      return [4];
    case "quick_stop_active":
      return [16];
    case "fault":
      return [15, 2, 3, 4];
    default:
      return [];
  }
}

// ------------------------------------------------------------------------------ geometry

export const DIAGRAM = { width: 600, height: 470, boxWidth: 180, boxHeight: 44 } as const;

export interface Box {
  x: number;
  y: number;
}

const LEFT = 70;
const RIGHT = 390;
const ROW = [50, 138, 226, 314, 402] as const;

export const STATE_BOXES: Readonly<Record<DriveStateName, Box>> = {
  not_ready_to_switch_on: { x: LEFT, y: ROW[0] },
  switch_on_disabled: { x: LEFT, y: ROW[1] },
  ready_to_switch_on: { x: LEFT, y: ROW[2] },
  switched_on: { x: LEFT, y: ROW[3] },
  operation_enabled: { x: LEFT, y: ROW[4] },
  fault_reaction_active: { x: RIGHT, y: ROW[0] },
  fault: { x: RIGHT, y: ROW[1] },
  quick_stop_active: { x: RIGHT, y: ROW[4] },
};

export interface Arrow {
  number: number;
  /** Polyline points; the arrowhead sits on the last one. */
  points: readonly (readonly [number, number])[];
  /** Where the transition's number is written. */
  label: readonly [number, number];
}

const R = LEFT + DIAGRAM.boxWidth; // right edge of the left column
const C = LEFT + DIAGRAM.boxWidth / 2; // centre of the left column
const H = DIAGRAM.boxHeight;
const FC = RIGHT + DIAGRAM.boxWidth / 2; // centre of the right column

/**
 * The arrows, laid out so that none crosses another: 8 and 9 run on the left of the main
 * column, 10, 12 and 15 enter Switch on disabled from the right at different heights, each
 * outside the next.
 */
export const ARROWS: readonly Arrow[] = [
  {
    number: 0,
    points: [
      [C, 14],
      [C, ROW[0]],
    ],
    label: [C + 8, 36],
  },
  {
    number: 1,
    points: [
      [C, ROW[0] + H],
      [C, ROW[1]],
    ],
    label: [C + 8, ROW[0] + H + 26],
  },
  {
    number: 2,
    points: [
      [C - 20, ROW[1] + H],
      [C - 20, ROW[2]],
    ],
    label: [C - 36, ROW[1] + H + 26],
  },
  {
    number: 7,
    points: [
      [C + 20, ROW[2]],
      [C + 20, ROW[1] + H],
    ],
    label: [C + 28, ROW[1] + H + 26],
  },
  {
    number: 3,
    points: [
      [C - 20, ROW[2] + H],
      [C - 20, ROW[3]],
    ],
    label: [C - 36, ROW[2] + H + 26],
  },
  {
    number: 6,
    points: [
      [C + 20, ROW[3]],
      [C + 20, ROW[2] + H],
    ],
    label: [C + 28, ROW[2] + H + 26],
  },
  {
    number: 4,
    points: [
      [C - 20, ROW[3] + H],
      [C - 20, ROW[4]],
    ],
    label: [C - 36, ROW[3] + H + 26],
  },
  {
    number: 5,
    points: [
      [C + 20, ROW[4]],
      [C + 20, ROW[3] + H],
    ],
    label: [C + 28, ROW[3] + H + 26],
  },
  {
    number: 8,
    points: [
      [LEFT, ROW[4] + 14],
      [46, ROW[4] + 14],
      [46, ROW[2] + 22],
      [LEFT, ROW[2] + 22],
    ],
    label: [50, ROW[3] + 6],
  },
  {
    number: 9,
    points: [
      [LEFT, ROW[4] + 32],
      [20, ROW[4] + 32],
      [20, ROW[1] + 22],
      [LEFT, ROW[1] + 22],
    ],
    label: [6, ROW[2] + 20],
  },
  {
    number: 10,
    points: [
      [R, ROW[3] + 22],
      [285, ROW[3] + 22],
      [285, ROW[1] + 34],
      [R, ROW[1] + 34],
    ],
    label: [290, ROW[2] + 40],
  },
  {
    number: 11,
    points: [
      [R, ROW[4] + 12],
      [RIGHT, ROW[4] + 12],
    ],
    label: [(R + RIGHT) / 2 - 6, ROW[4] + 6],
  },
  {
    number: 16,
    points: [
      [RIGHT, ROW[4] + 32],
      [R, ROW[4] + 32],
    ],
    label: [(R + RIGHT) / 2 - 6, ROW[4] + 48],
  },
  {
    number: 12,
    points: [
      [FC, ROW[4]],
      [FC, 290],
      [320, 290],
      [320, ROW[1] + 17],
      [R, ROW[1] + 17],
    ],
    label: [FC + 8, 350],
  },
  {
    number: 13,
    points: [
      [FC, 14],
      [FC, ROW[0]],
    ],
    label: [FC + 8, 36],
  },
  {
    number: 14,
    points: [
      [FC, ROW[0] + H],
      [FC, ROW[1]],
    ],
    label: [FC + 8, ROW[0] + H + 26],
  },
  {
    number: 15,
    points: [
      [RIGHT, ROW[1] + 5],
      [R, ROW[1] + 5],
    ],
    label: [(R + RIGHT) / 2, ROW[1] - 2],
  },
];

/** SVG path data of a polyline. */
export function polylinePath(points: Arrow["points"]): string {
  return points.map(([x, y], i) => `${i === 0 ? "M" : "L"}${x} ${y}`).join(" ");
}
