// Canned answers for the PDO page tests: node 1, an MDi-S1-C (byte-granular), PP mapping.
import type { BusLoad, Pdo, PdoRules } from "./types";

export { INFO, TREE } from "../../test/fixtures/node"; // shared with the Scope page's tests

function pdo(over: Partial<Pdo> & Pick<Pdo, "kind" | "number">): Pdo {
  return {
    cob_id: (over.kind === "rpdo" ? 0x201 : 0x181) + 0x100 * (over.number - 1),
    valid: false,
    transmission_type: 255,
    inhibit_time_100us: 0,
    event_timer_ms: 0,
    sync_start: 0,
    mapping: [],
    transmission: "",
    ...over,
  };
}

export const DEVICE: Pdo[] = [
  pdo({
    kind: "rpdo",
    number: 1,
    valid: true,
    mapping: [{ index: 0x6040, subindex: 0, bits: 16, name: "Controlword" }],
  }),
  pdo({ kind: "rpdo", number: 2 }),
  pdo({
    kind: "tpdo",
    number: 1,
    valid: true,
    transmission_type: 5,
    inhibit_time_100us: 25,
    event_timer_ms: 100,
    mapping: [
      { index: 0x6041, subindex: 0, bits: 16, name: "Statusword" },
      { index: 0x2fff, subindex: 3, bits: 8, name: null },
    ],
  }),
  pdo({ kind: "tpdo", number: 2 }),
];

export const RECOMMENDED: Pdo[] = [
  pdo({
    kind: "rpdo",
    number: 1,
    valid: true,
    transmission_type: 1,
    mapping: [
      { index: 0x6040, subindex: 0, bits: 16, name: "Controlword" },
      { index: 0x607a, subindex: 0, bits: 32, name: "Target position" },
    ],
  }),
  pdo({
    kind: "tpdo",
    number: 1,
    valid: true,
    transmission_type: 1,
    mapping: [
      { index: 0x6041, subindex: 0, bits: 16, name: "Statusword" },
      { index: 0x6064, subindex: 0, bits: 32, name: "Position actual value" },
    ],
  }),
];

export const LOAD: BusLoad = {
  bitrate: 500_000,
  master_period_ms: 10,
  sync_period_us: 1000,
  sync_bits_per_s: 47_000,
  nodes: [
    {
      node: 1,
      bits_per_s: 400_000,
      percent: 80,
      pdos: [
        {
          kind: "tpdo",
          number: 1,
          cob_id: 0x181,
          frames_per_s: 1000,
          bits_per_frame: 95,
          bits_per_s: 95_000,
          basis: "every SYNC at 1000 µs",
        },
      ],
    },
  ],
  total_bits_per_s: 400_000,
  percent: 80,
  threshold_percent: 70,
  over_threshold: true,
  notes: ["Worst-case bit stuffing counted."],
};

/** How the MDi-S1-C takes PDOs: whole bytes, CAN ids of PDOs 1–4 fixed, no RTR. */
export const RULES: PdoRules = {
  byte_granular: true,
  fixed_cob_ids: 4,
  rtr_supported: false,
  rpdo_count: 4,
  tpdo_count: 4,
  procedure:
    "invalidate the COB-ID, mapping count 0, entries, count, communication parameters, COB-ID (MDi-S1-C CANopen manual §2.5.4)",
  needs_pre_operational: false,
};

/** A CiA 402 drive's rules: bit-granular, every COB-ID free, changes outside Operational. */
export const CIA402_RULES: PdoRules = {
  ...RULES,
  byte_granular: false,
  fixed_cob_ids: 0,
  rtr_supported: true,
  procedure:
    "Pre-operational, then the MDi order, then back to the previous NMT state (Nanotec CANopen article: no PDO changes in Operational, abort 08000022)",
  needs_pre_operational: true,
};

/** The bus-load answer for the settings in `request`'s query, compared as the server does. */
export function loadFor(request: Request, percent = LOAD.percent): BusLoad {
  const query = new URL(request.url).searchParams;
  const threshold = Number(query.get("threshold") ?? 70);
  return {
    ...LOAD,
    master_period_ms: Number(query.get("master_period_ms") ?? 10),
    percent,
    threshold_percent: threshold,
    over_threshold: percent > threshold,
  };
}

/** A live capture of node 1: two TPDOs decoded, the master's two RPDOs not seen. */
export const LIVE = {
  node: 1,
  active: true,
  since: 1_700_000_000,
  pdos: [
    {
      cob_id: 0x181,
      kind: "tpdo",
      number: 1,
      frames: 42,
      rate_hz: 100,
      age_ms: 5,
      values: [
        {
          index: 0x6041,
          subindex: 0,
          name: "Statusword",
          value: 592,
          raw: "50 02",
          unit: "",
          text: "Switch on disabled",
          display: "0x0250",
        },
        {
          index: 0x6077,
          subindex: 0,
          name: "Torque actual value",
          value: 0,
          raw: "00 00",
          unit: "0.1 %",
          text: null,
          display: "0.0 %",
        },
        {
          index: 0x6064,
          subindex: 0,
          name: "Position actual value",
          value: 1234,
          raw: "D2 04 00 00",
          unit: "inc",
          text: null,
        },
      ],
    },
    {
      cob_id: 0x281,
      kind: "tpdo",
      number: 2,
      frames: 1,
      rate_hz: null, // one frame: no rate yet
      age_ms: 5,
      values: [
        {
          index: 0x6061,
          subindex: 0,
          name: null,
          value: 1,
          raw: "01",
          unit: "",
          text: "Profile position",
        },
      ],
    },
    { cob_id: 0x201, kind: "rpdo", number: 1, frames: 0, rate_hz: null, age_ms: null, values: [] },
    { cob_id: 0x301, kind: "rpdo", number: 2, frames: 0, rate_hz: null, age_ms: null, values: [] },
  ],
  drive_page: "The Drive page does not send its commands in these RPDOs: it uses SDO.",
};
