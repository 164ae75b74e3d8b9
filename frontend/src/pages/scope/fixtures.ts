// Canned answers for the Scope page tests: node 1 (MDi-S1-C), position and velocity in TPDO2,
// a vendor object polled by SDO.
import type { NodeInfo } from "../../api/types";
import { INFO, TREE } from "../../test/fixtures/node";
import type { BusLoad, Capture, CaptureSignal, ScopePlan, ScopeViewer } from "./types";

export { INFO, TREE };

export const INFO_2: NodeInfo = { ...INFO, node: 2, name: "Kinco Servo", profile_label: "Kinco" };

function signal(
  over: Partial<CaptureSignal> & Pick<CaptureSignal, "index" | "name">,
): CaptureSignal {
  return {
    node: 1,
    subindex: 0,
    key: over.name.toLowerCase().replace(/\W+/g, "_"),
    source: "pdo",
    quantity: "other",
    unit: "",
    raw_unit: "",
    scale: 1,
    bits: 32,
    tpdo: 2,
    cob_id: 0x281,
    rate_hz: null,
    samples: 0,
    last_value: null,
    note: null,
    ...over,
  };
}

export const POSITION = signal({
  index: 0x6064,
  name: "Position actual value",
  key: "position_actual",
  quantity: "position",
  unit: "rev",
  raw_unit: "user units",
  scale: 1e-5,
});
export const VELOCITY = signal({
  index: 0x606c,
  name: "Velocity actual value",
  key: "velocity_actual",
  quantity: "velocity",
  unit: "rpm",
  raw_unit: "rpm",
});
export const STATUSWORD = signal({
  index: 0x6041,
  name: "Statusword",
  key: "statusword",
  quantity: "statusword",
  bits: 16,
  tpdo: 3,
  cob_id: 0x381,
  note: "added: the CiA 402 state lane",
});
export const OVERSPEED = signal({
  index: 0x2006,
  subindex: 8,
  name: "Overspeed",
  source: "sdo",
  tpdo: null,
  cob_id: null,
  note: "polled by SDO: it is not PDO-mappable in this drive's dictionary",
});

export const LOAD: BusLoad = {
  bitrate: 500000,
  sync_period_us: 1000,
  sync_bits_per_s: 55000,
  nodes: [{ node: 1, bits_per_s: 210000, percent: 42, pdos: [] }],
  total_bits_per_s: 265000,
  percent: 53,
  threshold_percent: 100,
  over_threshold: false,
  master_period_ms: 10,
  notes: ["RPDOs are not counted: ServoDesk sends none during a capture"],
};

export const PLAN: ScopePlan = {
  ok: true,
  signals: [POSITION, VELOCITY, STATUSWORD],
  bus_load: LOAD,
  problems: [],
  notes: [],
};

export const VIEWER: ScopeViewer = {
  url: "/rerun/?url=rerun%2Bhttp%3A%2F%2Flocalhost%3A3000%2Fproxy",
  grpc_url: "rerun+http://localhost:3000/proxy",
  version: "0.41.0",
  running: true,
};

export function capture(over: Partial<Capture> = {}): Capture {
  return {
    id: 7,
    name: "axis 1",
    state: "running",
    created: 1_790_000_000,
    started: 1_790_000_000,
    trigger_time: 1_790_000_000.2,
    ended: null,
    signals: [
      { ...POSITION, samples: 1500, rate_hz: 999, last_value: 2.5 },
      { ...VELOCITY, samples: 1500, rate_hz: 999, last_value: 120 },
      { ...STATUSWORD, samples: 1500, rate_hz: 999, last_value: 0x637 },
    ],
    nodes: [1],
    sync_period_us: 1000,
    duration_s: 5,
    trigger: { kind: "none", edge: "rising", pre_s: 0, mode: "single", keep: 10 },
    samples: 4500,
    lost: 0,
    size_bytes: 0,
    bus_load_percent: 53,
    recording_id: "rec-7",
    series: null,
    error: null,
    notes: ["node 1 put into Operational for the capture"],
    ...over,
  };
}
