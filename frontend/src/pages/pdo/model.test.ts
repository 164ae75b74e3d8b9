import { describe, expect, it } from "vitest";

import {
  draftChanges,
  fitProblem,
  formatCobId,
  frameLayout,
  inhibitFromMs,
  fitRules,
  fixedCobIdReason,
  formatPercent,
  formatRate,
  inhibitMs,
  isSynchronous,
  mergePdos,
  moveEntry,
  parseCobId,
  placeProblems,
  problemText,
  sortPdos,
  transmissionWords,
  typeBits,
  type ObjectInfo,
} from "./model";
import { inChinese } from "../../test/inChinese";
import type { MappedObject, Pdo, PdoRules, Problem } from "./types";

function object(over: Partial<ObjectInfo> = {}): ObjectInfo {
  return {
    index: 0x6040,
    subindex: 0,
    name: "Controlword",
    unit: "",
    access: "rw",
    dataTypeName: "UNSIGNED16",
    bits: 16,
    mappable: true,
    ...over,
  };
}

function entry(index: number, bits: number, subindex = 0): MappedObject {
  return { index, subindex, bits, name: null };
}

function pdo(over: Partial<Pdo> = {}): Pdo {
  return {
    kind: "rpdo",
    number: 1,
    cob_id: 0x201,
    valid: true,
    transmission_type: 255,
    inhibit_time_100us: 0,
    event_timer_ms: 0,
    sync_start: 0,
    mapping: [],
    transmission: "",
    ...over,
  };
}

describe("transmissionWords", () => {
  it.each([
    [0, "tpdo", "synchronous, acyclic (at the next SYNC after a change)"],
    [0, "rpdo", "synchronous (applied at the next SYNC)"],
    [1, "tpdo", "every SYNC"],
    [2, "tpdo", "every 2nd SYNC"],
    [3, "tpdo", "every 3rd SYNC"],
    [5, "tpdo", "every 5th SYNC"],
    [11, "tpdo", "every 11th SYNC"],
    [21, "tpdo", "every 21st SYNC"],
    [5, "rpdo", "synchronous"],
    [241, "tpdo", "reserved (241)"],
    [252, "tpdo", "sampled at SYNC, sent on remote request"],
    [253, "tpdo", "sent on remote request"],
    [254, "tpdo", "on change + event timer (manufacturer-specific event)"],
    [255, "tpdo", "on change + event timer (device-profile event)"],
    [255, "rpdo", "applied on arrival (device-profile event)"],
  ] as const)("type %i of a %s reads %j", (type, kind, words) => {
    expect(transmissionWords(type, kind)).toBe(words);
  });

  it.each([
    [0, true],
    [240, true],
    [241, false],
    [252, true],
    [253, false],
    [255, false],
  ])("type %i synchronous: %s", (type, sync) => {
    expect(isSynchronous(type)).toBe(sync);
  });
});

describe("numbers as shown", () => {
  it.each([
    [0x181, "0x181"],
    [0x7f, "0x07F"],
    [0x7ff, "0x7FF"],
  ])("COB-ID %i is %s", (value, text) => {
    expect(formatCobId(value)).toBe(text);
  });

  it.each([
    ["0x181", 0x181],
    ["181h", 0x181],
    [" 2A1 ", 0x2a1],
    ["800", null],
    ["0", null],
    ["x", null],
    ["", null],
  ])("COB-ID %j parses to %s", (text, value) => {
    expect(parseCobId(text)).toBe(value);
  });

  it.each([
    [0, 0],
    [10, 1],
    [25, 2.5],
    [65535, 6553.5],
  ])("inhibit %i × 100 µs is %f ms", (raw, ms) => {
    expect(inhibitMs(raw)).toBe(ms);
    expect(inhibitFromMs(ms)).toBe(raw);
  });

  it.each([
    ["BOOLEAN", 1],
    ["INTEGER8", 8],
    ["UNSIGNED16", 16],
    ["INTEGER32", 32],
    ["REAL32", 32],
    ["UNSIGNED64", 64],
    ["VISIBLE_STRING", null],
    ["DOMAIN", null],
  ])("%s is %s bits", (name, bits) => {
    expect(typeBits(name)).toBe(bits);
  });
});

describe("numbers in the load and live tables", () => {
  it.each([
    [null, "—"], // fewer than two frames: no rate yet
    [undefined, "—"],
    [0, "0/s"],
    [0.25, "0.3/s"],
    [9.94, "9.9/s"],
    [9.96, "10/s"],
    [100, "100/s"],
  ])("rate %s is %s", (value, text) => {
    expect(formatRate(value)).toBe(text);
  });

  it.each([
    [2.34, "2.3 %"],
    [9.96, "10 %"],
    [46.4, "46 %"],
  ])("load %s is %s", (value, text) => {
    expect(formatPercent(value)).toBe(text);
  });
});

describe("the node's rules", () => {
  const mdi: PdoRules = {
    byte_granular: true,
    fixed_cob_ids: 4,
    rtr_supported: false,
    rpdo_count: 4,
    tpdo_count: 4,
    procedure: "invalidate the COB-ID, …",
    needs_pre_operational: false,
  };

  it("takes byte granularity and fixed COB-IDs from the server, permissive while loading", () => {
    expect(fitRules(mdi)).toEqual({ byteGranular: true, fixedCobIds: 4 });
    expect(fitRules(undefined)).toEqual({ byteGranular: false, fixedCobIds: 0 });
  });

  it.each([
    [
      1,
      4,
      "This drive fixes the CAN id of PDOs 1–4 to the pre-defined set; only the valid bit can change.",
    ],
    [4, 4, "PDOs 1–4"],
    [5, 4, null],
    [1, 1, "the CAN id of PDO 1 to"],
    [2, 1, null],
    [1, 0, null],
  ])("PDO %s with %s fixed COB-IDs: %s", (number, fixed, expected) => {
    const reason = fixedCobIdReason({ number }, { byteGranular: false, fixedCobIds: fixed });
    if (expected === null) expect(reason).toBeNull();
    else expect(reason).toContain(expected);
  });
});

describe("placeProblems", () => {
  const tpdo1 = pdo({
    kind: "tpdo",
    mapping: [entry(0x6041, 16), entry(0x6064, 32), entry(0x6041, 16)],
  });
  const problem = (index: number | null, subindex: number | null = 0): Problem => ({
    kind: "tpdo",
    number: 1,
    message: `about ${index ?? "the PDO"}:${subindex ?? "-"}`,
    index,
    subindex,
  });

  it("puts each problem at the object, field or PDO it names", () => {
    const atObject = problem(0x6064);
    const twice = problem(0x6041);
    const entry3 = problem(0x1a00, 3); // the 3rd mapping entry
    const count = problem(0x1a00, 0); // the mapping count: the whole frame
    const cobId = problem(0x1800, 1);
    const transmission = problem(0x1800, 2);
    const eventTimer = problem(0x1800, 5);
    const otherPdo = problem(0x1801, 1);
    const whole = problem(null, null);
    const notMapped = problem(0x607a);
    const placed = placeProblems(tpdo1, [
      atObject,
      twice,
      entry3,
      count,
      cobId,
      transmission,
      eventTimer,
      otherPdo,
      whole,
      notMapped,
    ]);
    expect(placed.atEntry).toEqual(
      new Map([
        [1, [atObject]],
        [0, [twice]],
        [2, [twice, entry3]],
      ]),
    );
    expect(placed.atField).toEqual(
      new Map([
        ["cob_id", [cobId]],
        ["transmission_type", [transmission]],
        ["event_timer", [eventTimer]],
      ]),
    );
    expect(placed.rest).toEqual([count, otherPdo, whole, notMapped]);
  });

  it("reads an RPDO's parameters at 14xxh / 16xxh", () => {
    const rpdo2 = pdo({ number: 2, mapping: [entry(0x6040, 16)] });
    const placed = placeProblems(rpdo2, [
      { kind: "rpdo", number: 2, message: "a", index: 0x1401, subindex: 2 },
      { kind: "rpdo", number: 2, message: "b", index: 0x1601, subindex: 1 },
    ]);
    expect([...placed.atField.keys()]).toEqual(["transmission_type"]);
    expect([...placed.atEntry.keys()]).toEqual([0]);
  });
});

describe("frameLayout", () => {
  const known = new Map([[0x6041, object({ index: 0x6041, name: "Statusword", access: "ro" })]]);
  const lookup = (index: number): ObjectInfo | undefined => known.get(index);

  it("packs objects one after the other from bit 0", () => {
    const layout = frameLayout([entry(0x6041, 16), entry(0x6064, 32), entry(0x6061, 8)], lookup);
    expect(layout.blocks.map((b) => [b.startBit, b.bits])).toEqual([
      [0, 16],
      [16, 32],
      [48, 8],
    ]);
    expect(layout.usedBits).toBe(56);
    expect(layout.bytes).toBe(7);
  });

  it("names known objects and keeps unknown ones raw", () => {
    const [first, second] = frameLayout(
      [entry(0x6041, 16), { index: 0x2000, subindex: 3, bits: 8, name: "From server" }],
      lookup,
    ).blocks;
    expect(first?.name).toBe("Statusword");
    expect(first?.known).toBe(true);
    expect(second?.name).toBe("From server");
    expect(second?.known).toBe(false);
  });

  it("marks what lies past 64 bits", () => {
    const layout = frameLayout([entry(0x6064, 32), entry(0x606c, 32), entry(0x6041, 16)], lookup);
    expect(layout.blocks.map((b) => b.overflow)).toEqual([false, false, true]);
    expect(layout.bytes).toBe(10);
  });

  it("counts bit-sized objects into partial bytes", () => {
    expect(frameLayout([entry(0x2000, 1), entry(0x2001, 3)], lookup).bytes).toBe(1);
  });
});

describe("fitProblem", () => {
  const byteRules = { byteGranular: true, fixedCobIds: 0 };
  const bitRules = { byteGranular: false, fixedCobIds: 0 };
  const full32 = [entry(0x6064, 32), entry(0x606c, 32)];
  const eight = Array.from({ length: 8 }, (_, i) => entry(0x2000 + i, 1));

  it.each([
    ["fits", pdo(), object(), bitRules, null],
    ["not mappable", pdo(), object({ mappable: false }), bitRules, "is not PDO-mappable"],
    [
      "no fixed size",
      pdo(),
      object({ bits: null, dataTypeName: "VISIBLE_STRING" }),
      bitRules,
      "no fixed size",
    ],
    ["RPDO needs writable", pdo(), object({ access: "ro" }), bitRules, "is read-only"],
    ["TPDO may read ro", pdo({ kind: "tpdo" }), object({ access: "ro" }), bitRules, null],
    [
      "TPDO needs readable",
      pdo({ kind: "tpdo" }),
      object({ access: "wo" }),
      bitRules,
      "write-only",
    ],
    [
      "whole bytes",
      pdo(),
      object({ bits: 1, dataTypeName: "BOOLEAN" }),
      byteRules,
      "whole bytes only",
    ],
    ["bits fine on CiA drive", pdo(), object({ bits: 1 }), bitRules, null],
    ["64 bits full", pdo({ mapping: full32 }), object(), bitRules, "has 0 of 64 left"],
    [
      "8 entries full",
      pdo({ mapping: eight }),
      object({ bits: 1 }),
      bitRules,
      "already maps 8 objects",
    ],
    [
      "exactly 64 fits",
      pdo({ mapping: [entry(0x6064, 32), entry(0x6041, 16)] }),
      object(),
      bitRules,
      null,
    ],
  ])("%s", (_name, target, candidate, rules, expected) => {
    const problem = fitProblem(target, candidate, rules);
    if (expected === null) expect(problem).toBeNull();
    else expect(problem).toContain(expected);
  });
});

describe("draft helpers", () => {
  it.each([
    [0, 2, ["b", "c", "a"]],
    [2, 0, ["c", "a", "b"]],
    [1, 1, ["a", "b", "c"]],
    [1, 9, ["a", "c", "b"]],
    [5, 0, ["a", "b", "c"]],
  ])("moveEntry %i → %i", (from, to, expected) => {
    expect(moveEntry(["a", "b", "c"], from, to)).toEqual(expected);
  });

  it("lists what a draft changes, in words", () => {
    const device = [pdo(), pdo({ kind: "tpdo", number: 1, cob_id: 0x181 })];
    const draft = [
      pdo(),
      pdo({
        kind: "tpdo",
        number: 1,
        cob_id: 0x181,
        transmission_type: 1,
        inhibit_time_100us: 50,
        mapping: [{ index: 0x6041, subindex: 0, bits: 16, name: "Statusword" }],
      }),
    ];
    expect(draftChanges(device, draft)).toEqual([
      {
        pdo: draft[1],
        changes: ["transmission 255 → 1 (every SYNC)", "inhibit 0 → 5 ms", "mapping → Statusword"],
      },
    ]);
  });

  it("says when a PDO becomes valid or gets another COB-ID", () => {
    const [change] = draftChanges([pdo({ valid: false })], [pdo({ cob_id: 0x301 })]);
    expect(change?.changes).toEqual(["COB-ID 0x201 → 0x301", "made valid"]);
  });

  it("merges a recommendation into the device's PDOs and sorts them", () => {
    const device = [pdo({ kind: "tpdo" }), pdo(), pdo({ number: 2 })];
    const merged = mergePdos(device, [pdo({ number: 2, cob_id: 0x301 }), pdo({ number: 5 })]);
    expect(merged.map((p) => [p.kind, p.number, p.cob_id])).toEqual([
      ["tpdo", 1, 0x201],
      ["rpdo", 1, 0x201],
      ["rpdo", 2, 0x301],
      ["rpdo", 5, 0x201],
    ]);
    expect(sortPdos(merged).map((p) => `${p.kind}${p.number}`)).toEqual([
      "rpdo1",
      "rpdo2",
      "rpdo5",
      "tpdo1",
    ]);
  });
});

describe("problemText in zh-CN", () => {
  inChinese();

  it("says a problem of the server's in Chinese, who uses the CAN id too", () => {
    const used: Problem = {
      kind: "tpdo",
      number: 1,
      message: "TPDO1 CAN id 182h is already used by node 2 EMCY",
      index: 0x1800,
      subindex: 1,
      message_id: "pdo.can_id_used",
      params: {
        pdo: "TPDO1",
        can_id: "182",
        owner: "node 2 EMCY",
        owner_id: "owner.node_service",
        owner_node: 2,
        owner_service: "EMCY",
      },
    };
    expect(problemText(used)).toBe("TPDO1 的 CAN ID 182h 已被 节点 2 的 EMCY 占用");
  });

  it("names a synchronous PDO's transmission type in the page's own words", () => {
    const warning: Problem = {
      kind: "tpdo",
      number: 1,
      message: "TPDO1 is synchronous (every SYNC) but no SYNC …",
      index: 0x1800,
      subindex: 2,
      message_id: "pdo.sync_missing_ask",
      params: { pdo: "TPDO1", words: "every SYNC", t: 1 },
    };
    expect(problemText(warning)).toMatch(/^TPDO1 为同步传输（每个 SYNC），/);
  });

  it("shows the server's English for a problem without an id", () => {
    const plain: Problem = { kind: "rpdo", number: 2, message: "RPDO2 something new", params: {} };
    expect(problemText(plain)).toBe("RPDO2 something new");
  });
});
