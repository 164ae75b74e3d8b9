import { describe, expect, it } from "vitest";

import { describeStep, edgeOf, homingDrawing, HOMING_GEOMETRY, switchOf } from "./homingPath";
import {
  ARROWS,
  enablePath,
  STATE_BOXES,
  stateFromStatusword,
  transitionNumber,
  TRANSITIONS,
  transitionsFor,
} from "./stateMachine";
import { homingStatus, statusLamps, wordHex } from "./statusBits";
import type { PathStep } from "./types";
import { checkRange, formatInc, formatPct, formatRev, formatRpm, modeLabel } from "./units";

describe("stateFromStatusword", () => {
  it.each([
    [0x0000, "not_ready_to_switch_on"],
    [0x0250, "switch_on_disabled"],
    [0x0231, "ready_to_switch_on"],
    [0x0233, "switched_on"],
    [0x0237, "operation_enabled"],
    [0x1637, "operation_enabled"],
    [0x0217, "quick_stop_active"],
    [0x021f, "fault_reaction_active"],
    [0x0218, "fault"],
    [0x0208, "fault"],
  ])("%s → %s", (word, state) => {
    expect(stateFromStatusword(word)).toBe(state);
  });

  it("knows no state for an undefined pattern", () => {
    expect(stateFromStatusword(0x0001)).toBeNull();
  });
});

describe("transitions", () => {
  it("numbers 0 to 16 once each, every one drawn", () => {
    const numbers = TRANSITIONS.map((t) => t.number).sort((a, b) => a - b);
    expect(numbers).toEqual([...Array(17).keys()]);
    expect(ARROWS.map((a) => a.number).sort((a, b) => a - b)).toEqual(numbers);
  });

  it.each([
    ["shutdown", "switch_on_disabled", [2]],
    ["shutdown", "switched_on", [6]],
    ["shutdown", "operation_enabled", [8]],
    ["switch_on", "ready_to_switch_on", [3]],
    ["enable_operation", "switched_on", [4]],
    ["enable_operation", "quick_stop_active", [16]],
    ["disable_voltage", "operation_enabled", [9]],
    ["quick_stop", "operation_enabled", [11]],
    ["fault_reset", "fault", [15]],
    ["fault_reset", "switched_on", []],
  ] as const)("%s from %s takes %j", (command, state, numbers) => {
    expect(transitionsFor(command, state).map((t) => t.number)).toEqual(numbers);
  });

  it.each([
    ["enable operation (4)", 4],
    ["fault reset (15)", 15],
    ["12", 12],
    [null, null],
    ["shutdown", null],
    ["odd (99)", null],
  ])("reads the number in %j", (text, number) => {
    expect(transitionNumber(text)).toBe(number);
  });

  it.each([
    ["switch_on_disabled", [2, 3, 4]],
    ["fault", [15, 2, 3, 4]],
    ["quick_stop_active", [16]],
    ["operation_enabled", []],
  ] as const)("enables from %s via %j", (state, path) => {
    expect(enablePath(state)).toEqual(path);
  });

  it("draws every arrow's end on the edge of the state it enters", () => {
    for (const transition of TRANSITIONS) {
      const arrow = ARROWS.find((a) => a.number === transition.number);
      const end = arrow?.points.at(-1);
      const box = STATE_BOXES[transition.to];
      expect(end, `arrow ${transition.number}`).toBeDefined();
      if (!end) continue;
      const [x, y] = end;
      const onEdge =
        ((x === box.x || x === box.x + 180) && y >= box.y && y <= box.y + 44) ||
        ((y === box.y || y === box.y + 44) && x >= box.x && x <= box.x + 180);
      expect(onEdge, `arrow ${transition.number} ends at ${x},${y}`).toBe(true);
    }
  });
});

describe("statusLamps", () => {
  it("lights the bits of the word and names 12/13 by mode", () => {
    const lamps = statusLamps(0x1637, "hm");
    expect(lamps).toHaveLength(16);
    expect(lamps.filter((l) => l.on).map((l) => l.bit)).toEqual([0, 1, 2, 4, 5, 9, 10, 12]);
    expect(lamps[12]?.name).toBe("Homing attained");
    expect(lamps[13]?.name).toBe("Homing error");
    expect(statusLamps(0, "pp")[12]?.name).toBe("Set-point acknowledge");
    expect(statusLamps(0, null)[12]?.name).toBe("Operation mode specific");
  });

  it("prefers the server's names", () => {
    const lamps = statusLamps(0x0008, null, [{ bit: 3, name: "Fault (alarm)", on: true }]);
    expect(lamps[3]).toEqual({ bit: 3, name: "Fault (alarm)", on: true, tone: "bad" });
  });

  it.each([
    [0x0237, "0237h"],
    [0x1f, "001Fh"],
  ])("writes %s as %s", (value, text) => {
    expect(wordHex(value)).toBe(text);
  });

  it.each([
    [0x0237, "Homing in progress"],
    [0x1637, "Homing attained"],
    [0x2637, "Homing error"],
    [0x0637, "Homing interrupted or not started"],
  ])("homing bits of %s read %s", (word, text) => {
    expect(homingStatus(word).text).toBe(text);
  });
});

describe("units", () => {
  it.each([
    [formatRev(1.23456), "1.235 rev"],
    [formatRev(-0.0001), "0.000 rev"],
    [formatRev(-2), "−2.000 rev"],
    [formatInc(1234567), "1\u202f234\u202f567 inc"],
    [formatInc(-131072), "−131\u202f072 inc"],
    [formatRpm(null), "—"],
    [formatRpm(-300), "−300.0 rpm"],
    [formatPct(12.34), "12.3 %"],
    [modeLabel("pv"), "Profile velocity (PV)"],
    [modeLabel(null), "none"],
    [modeLabel("x7"), "x7"],
  ])("%s", (shown, expected) => {
    expect(shown).toBe(expected);
  });

  it.each([
    ["100", { max: 3000 }, 100, null],
    ["", {}, null, "Enter a number"],
    ["abc", {}, null, "Enter a number"],
    ["4000", { max: 3000 }, null, "At most 3000"],
    ["-5", { min: 0 }, null, "At least 0"],
    ["0", { positive: true }, null, "Must be above 0"],
    ["\u22121,5", {}, -1.5, null],
  ])("checkRange(%j, %j)", (text, bounds, value, error) => {
    expect(checkRange(text, bounds)).toEqual({ value, error });
  });
});

const step = (
  direction: PathStep["direction"],
  speed: PathStep["speed"],
  until: string,
): PathStep => ({ direction, speed, until });

describe("homing path", () => {
  it.each([
    ["negative limit switch rises", "negative_limit", "rise"],
    ["negative limit switch falls", "negative_limit", "fall"],
    ["positive limit switch (P-OT) is reached", "positive_limit", "rise"],
    ["home switch rises", "home", "rise"],
    ["home switch falls", "home", "fall"],
    ["leaving the home switch", "home", "fall"],
    ["index pulse", null, "rise"],
  ])("%j names %s on its %s edge", (until, name, edge) => {
    expect(switchOf(until)).toBe(name);
    expect(edgeOf(until)).toBe(edge);
  });

  it("method 17: fast negative into N-OT, reverse, slow out of it", () => {
    const drawing = homingDrawing([
      step("negative", "fast", "negative limit switch rises"),
      step("positive", "slow", "negative limit switch falls"),
    ]);
    const G = HOMING_GEOMETRY;
    expect(drawing.switches.map((s) => s.label)).toEqual(["N-OT"]);
    const [first, second] = drawing.arrows;
    expect(first?.x1).toBe(G.left + G.limitWidth - G.overshoot); // decelerates inside
    expect(first?.x0).toBeGreaterThan(first?.x1 ?? 0);
    expect(second?.x0).toBe(first?.x1);
    expect(second?.x1).toBe(G.left + G.limitWidth); // stops on the falling edge
    expect(second?.y).toBeGreaterThan(first?.y ?? 0);
    expect(second?.join).toEqual({ x: first?.x1, y0: first?.y, y1: second?.y, reversal: true });
    expect(drawing.end).toBe(G.left + G.limitWidth);
    expect(drawing.axisY).toBeGreaterThan(second?.y ?? 0);
    expect(drawing.homeAnchor).toBe("start"); // right of the N-OT label
  });

  it("method 23 reversing on P-OT draws both limits around the home switch", () => {
    const drawing = homingDrawing([
      step("positive", "fast", "positive limit switch rises"),
      step("negative", "fast", "home switch rises"),
      step("negative", "slow", "home switch falls"),
    ]);
    expect(drawing.switches.map((s) => s.label)).toEqual(["HW", "P-OT"]);
    const home = drawing.switches[0];
    const [a, b, c] = drawing.arrows;
    expect(drawing.start).toBeGreaterThan(home?.x1 ?? 0); // starts between HW and P-OT
    expect(a?.x1).toBeGreaterThan(drawing.start);
    expect(b?.x1).toBeLessThan(home?.x1 ?? 0); // inside HW after its rising edge
    expect(c?.x1).toBe(home?.x0); // leaves HW on the negative side
    expect(b?.join?.reversal).toBe(true);
    expect(c?.join?.reversal).toBe(false); // fast to slow, same direction
    expect(drawing.homeAnchor).toBe("end"); // left of the HW label
  });

  it("method 35 has no steps: the axis alone", () => {
    const drawing = homingDrawing([]);
    expect(drawing.arrows).toEqual([]);
    expect(drawing.switches).toEqual([]);
    expect(drawing.end).toBe(drawing.start);
    expect(drawing.homeAnchor).toBe("middle");
  });

  it("describes a step in words", () => {
    expect(describeStep(step("negative", "fast", "negative limit switch rises"))).toBe(
      "fast negative until negative limit switch rises",
    );
  });
});
