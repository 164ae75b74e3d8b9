import { describe, expect, it } from "vitest";

import { TREE } from "./fixtures";
import {
  DEFAULT_FORM,
  DEFAULT_TRIGGER,
  MAX_SIGNALS,
  addSignal,
  buildRequest,
  findEntries,
  formatBytes,
  formatReading,
  levelHint,
  shortNumber,
  sourceText,
  startReason,
  triggerText,
  type ScopeForm,
  type SignalChoice,
  type TriggerForm,
} from "./model";
import { PLAN } from "./fixtures";

const POSITION: SignalChoice = { node: 1, index: 0x6064, subindex: 0, name: "Position" };
const VELOCITY: SignalChoice = { node: 1, index: 0x606c, subindex: 0, name: "Velocity" };

function form(over: Partial<ScopeForm> = {}, trigger: Partial<TriggerForm> = {}): ScopeForm {
  return {
    ...DEFAULT_FORM,
    signals: [POSITION, VELOCITY],
    ...over,
    trigger: { ...DEFAULT_TRIGGER, ...trigger },
  };
}

describe("buildRequest", () => {
  it("builds a free-running capture from the form", () => {
    expect(buildRequest(form({ name: "  axis 1 ", durationS: "2,5" }))).toEqual({
      ok: true,
      request: {
        signals: [
          { node: 1, index: 0x6064, subindex: 0 },
          { node: 1, index: 0x606c, subindex: 0 },
        ],
        sync_period_us: 1000,
        duration_s: 2.5,
        trigger: { kind: "none", edge: "rising", pre_s: 0, mode: "single", keep: 10 },
        name: "axis 1",
        start_nodes: true,
      },
    });
  });

  it("says what keeps the form from being sent", () => {
    const problem = (f: ScopeForm): string | null => {
      const built = buildRequest(f);
      return built.ok ? null : built.problem;
    };
    expect(problem(form({ signals: [] }))).toBe("Pick at least one signal");
    expect(problem(form({ syncPeriodUs: "400" }))).toMatch(
      /^SYNC period: .* from 500 to 1,000,000/,
    );
    expect(problem(form({ syncPeriodUs: "1000.5" }))).toMatch(/^SYNC period/);
    expect(problem(form({ durationS: "" }))).toMatch(/^Duration/);
    expect(problem(form({ durationS: "0" }))).toMatch(/^Duration/);
    expect(problem(form({}, { kind: "level", signal: "1:24676:0", level: "" }))).toMatch(
      /enter the level/,
    );
    expect(problem(form({}, { kind: "level", signal: "" }))).toMatch(/choose the signal/);
    expect(problem(form({}, { kind: "bit", node: 1, bit: "64" }))).toMatch(/0 to 63/);
    expect(problem(form({}, { kind: "state", node: null }))).toMatch(/choose the node/);
    expect(problem(form({ durationS: "2" }, { kind: "emcy", preS: "2" }))).toMatch(
      /shorter than the duration/,
    );
    expect(problem(form({}, { kind: "emcy", mode: "normal", keep: "0" }))).toMatch(/^Keep/);
  });

  it("builds each trigger kind as the API wants it", () => {
    const trigger = (t: Partial<TriggerForm>): unknown => {
      const built = buildRequest(form({}, t));
      return built.ok ? built.request.trigger : built.problem;
    };
    expect(
      trigger({
        kind: "level",
        signal: "1:24676:0",
        level: "100000",
        edge: "falling",
        preS: "0.5",
      }),
    ).toEqual({
      kind: "level",
      node: 1,
      index: 0x6064,
      subindex: 0,
      level: 100000,
      edge: "falling",
      pre_s: 0.5,
      mode: "single",
      keep: 10,
    });
    expect(trigger({ kind: "bit", node: 2, bit: "10" })).toMatchObject({
      kind: "bit",
      node: 2,
      bit: 10,
      index: null, // 6041h Statusword, the server's default
      subindex: null,
    });
    expect(trigger({ kind: "bit", node: 1, bit: "3", bitObject: "24829:0" })).toMatchObject({
      index: 0x60fd,
      subindex: 0,
    });
    expect(trigger({ kind: "emcy", node: null, mode: "normal", keep: "5" })).toMatchObject({
      kind: "emcy",
      node: null,
      mode: "normal",
      keep: 5,
    });
    expect(trigger({ kind: "state", node: 1, state: "" })).toMatchObject({ node: 1, state: null });
    expect(trigger({ kind: "state", node: 1, state: "fault" })).toMatchObject({ state: "fault" });
    // a free-running capture has no pre-trigger, whatever the field still says
    expect(trigger({ kind: "none", preS: "1" })).toMatchObject({ pre_s: 0 });
  });
});

describe("signals", () => {
  it("adds a signal once and at most 32", () => {
    expect(addSignal([POSITION], POSITION)).toEqual([POSITION]);
    expect(addSignal([POSITION], VELOCITY)).toEqual([POSITION, VELOCITY]);
    const full = Array.from({ length: MAX_SIGNALS }, (_, i) => ({
      ...POSITION,
      index: 0x2000 + i,
    }));
    expect(addSignal(full, VELOCITY)).toHaveLength(MAX_SIGNALS);
  });

  it("finds dictionary entries by address or name, readable ones only", () => {
    expect(findEntries(TREE.objects, "6064").entries.map((e) => e.name)).toEqual([
      "Position actual value",
    ]);
    expect(findEntries(TREE.objects, "velocity").entries[0]).toMatchObject({
      index: 0x606c,
      unit: "inc/s",
      pdoMappable: true,
    });
    expect(findEntries(TREE.objects, "60", 2)).toMatchObject({ total: 6 });
    expect(findEntries(TREE.objects, "60", 2).entries).toHaveLength(2);
  });
});

describe("what the page shows", () => {
  it("names a signal's source: the TPDO and its COB-ID, or SDO polling", () => {
    expect(sourceText({ source: "pdo", tpdo: 2, cob_id: 0x281 })).toBe("TPDO2 · COB-ID 0x281");
    expect(sourceText({ source: "sdo", tpdo: null, cob_id: null })).toBe("SDO polling");
  });

  it("formats readings with their unit, bit patterns in hex", () => {
    const position = { unit: "rev", quantity: "position", bits: 32 };
    expect(formatReading(12.345678, position)).toBe("12.346 rev");
    expect(formatReading(null, position)).toBe("—");
    expect(formatReading(0x637, { unit: "", quantity: "statusword", bits: 16 })).toBe("0x0637");
    expect(formatReading(120, { unit: "rpm", quantity: "velocity", bits: 32 })).toBe("120 rpm");
    expect(shortNumber(0.000123)).toBe("0.000123");
    expect(shortNumber(123456.7)).toBe("123,457");
    expect(shortNumber(-1234.5678)).toBe("-1,234.6");
    expect(shortNumber(5e-7)).toBe("5.000e-7");
  });

  it("formats sizes", () => {
    expect(formatBytes(512)).toBe("512 B");
    expect(formatBytes(732296)).toBe("715 KiB");
    expect(formatBytes(10_400_000)).toBe("9.9 MiB");
  });

  it("says a trigger in words", () => {
    const base = { edge: "rising", pre_s: 0, mode: "single", keep: 10 } as const;
    expect(triggerText({ ...base, kind: "none" })).toBe("free-running");
    expect(
      triggerText({ ...base, kind: "level", node: 1, index: 0x6064, subindex: 0, level: 5000 }),
    ).toBe("node 1 6064h:00 crosses 5000 (rising)");
    expect(triggerText({ ...base, kind: "bit", node: 2, bit: 3, edge: "either", pre_s: 0.5 })).toBe(
      "node 2 6041h:00 bit 3 (either edge), 0.5 s before",
    );
    expect(triggerText({ ...base, kind: "emcy", mode: "normal", keep: 5 })).toBe(
      "EMCY from any node, re-armed (keeps 5)",
    );
    expect(triggerText({ ...base, kind: "state", node: 3, state: "fault" })).toBe(
      "node 3 enters fault",
    );
  });

  it("explains the level in the signal's physical unit", () => {
    const position = { scale: 1e-5, unit: "rev", raw_unit: "user units" };
    expect(levelHint("250000", position)).toBe("raw, in user units = 2.5 rev");
    expect(levelHint("", position)).toBe("raw, in user units");
    expect(levelHint("5", undefined)).toBeNull();
  });

  it("says why Start is disabled", () => {
    const built = buildRequest(form());
    const checked = { plan: PLAN, error: null, checking: false };
    expect(startReason(built, checked, null)).toBeNull();
    expect(startReason(built, { ...checked, checking: true }, null)).toBe("Checking the plan…");
    expect(startReason(built, checked, { id: 4, state: "armed" })).toBe(
      "Capture 4 is armed: stop it before starting another",
    );
    expect(startReason(built, checked, { id: 4, state: "done" })).toBeNull();
    const over = { ...PLAN, ok: false, problems: ["the capture would load the bus to 107 %"] };
    expect(startReason(built, { ...checked, plan: over }, null)).toBe(
      "the capture would load the bus to 107 %",
    );
    expect(startReason(buildRequest(form({ signals: [] })), checked, null)).toBe(
      "Pick at least one signal",
    );
  });
});
