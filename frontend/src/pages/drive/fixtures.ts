// Canned answers of the motion routes for the Drive tab's tests.
import type { ControllerInfo, DriveState, HomingMethodInfo } from "./types";

export const DRIVE: DriveState = {
  node: 1,
  state: "switch_on_disabled",
  state_label: "Switch on disabled",
  statusword: 0x0250,
  status_bits: [],
  controlword: 0x0000,
  last_transition: null,
  mode: "pp",
  mode_display: "pp",
  supported_modes: ["pp", "pv", "pt", "hm", "ip"],
  position_inc: 131072,
  position_rev: 1,
  velocity_rpm: 0,
  torque_pct: 0,
  following_error_inc: 3,
  digital_inputs: 0,
  inputs: { negative_limit: false, positive_limit: false, home_switch: true },
  homed: false,
  homing: null,
  move: null,
  target_reached: true,
  fault: null,
  nmt_state: "operational",
  counts_per_rev: 131072,
  gear_ratio: null,
  limits: {
    max_velocity_rpm: 3000,
    max_torque_pct: 100,
    min_position_rev: -10,
    max_position_rev: 10,
  },
  pt_speed_limit: { rpm: 6000, source: "2006h:08 PA-103 Maximum speed" },
  sources: { statusword: "TPDO1", position: "TPDO2", velocity: "SDO", torque: "SDO" },
};

export const ENABLED: DriveState = {
  ...DRIVE,
  state: "operation_enabled",
  state_label: "Operation enabled",
  statusword: 0x0637,
  controlword: 0x000f,
  last_transition: "enable operation (4)",
};

export const CONTROLLER: ControllerInfo = {
  node: 1,
  holder: null,
  you: false,
  protection: {
    active: true,
    tool_node_id: 127,
    consumer_ms: 300,
    message: "Node 1 stops by itself when the tool's heartbeat is missing for 300 ms",
  },
};

export const METHODS: HomingMethodInfo[] = [
  {
    method: 17,
    name: "Negative limit switch",
    description: "Fast to N-OT, back slowly until it falls",
    path: [
      { direction: "negative", speed: "fast", until: "negative limit switch rises" },
      { direction: "positive", speed: "slow", until: "negative limit switch falls" },
    ],
  },
  {
    method: 35,
    name: "Current position",
    description: "The current position becomes 0",
    path: [],
  },
];
