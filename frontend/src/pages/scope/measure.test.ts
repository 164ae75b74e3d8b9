import { describe, expect, it } from "vitest";

import { DEFAULT_LANES, hasWord, parseLanes, toggleBit } from "./lanes";
import {
  formatDuration,
  formatNumber,
  initialCursors,
  nearestCursor,
  nudge,
  parseCursor,
  readoutRows,
  stepOf,
  timeAt,
  xAt,
} from "./measure";
import { envelopePath } from "./sparkline";
import type { Measurement } from "./types";

const SPAN = { start: -0.1, end: 0.9 }; // a 1 s capture with 100 ms before the trigger

describe("cursors", () => {
  it("start at a quarter and three quarters of the capture", () => {
    const at = initialCursors(SPAN);
    expect(at.a).toBeCloseTo(0.15);
    expect(at.b).toBeCloseTo(0.65);
  });

  it("map the overview's pixels to times and back, clamped to the capture", () => {
    expect(timeAt(400, 800, SPAN)).toBeCloseTo(0.4);
    expect(timeAt(-30, 800, SPAN)).toBe(-0.1);
    expect(timeAt(900, 800, SPAN)).toBe(0.9);
    expect(xAt(0.4, 800, SPAN)).toBeCloseTo(400);
    expect(xAt(5, 800, SPAN)).toBe(800);
  });

  it("a drag takes the nearer cursor", () => {
    expect(nearestCursor({ a: 0.1, b: 0.5 }, 0.2)).toBe("a");
    expect(nearestCursor({ a: 0.1, b: 0.5 }, 0.4)).toBe("b");
    expect(nearestCursor({ a: 0.3, b: 0.3 }, 0.3)).toBe("a");
  });

  it("keys move a cursor by a round step, Shift by ten, Home/End to the ends", () => {
    expect(stepOf(SPAN)).toBeCloseTo(0.005); // 1/200 of 1 s, rounded 1-2-5
    expect(stepOf({ start: 0, end: 0.3 })).toBeCloseTo(0.001);
    expect(nudge(0.2, "ArrowRight", false, SPAN)).toBeCloseTo(0.205);
    expect(nudge(0.2, "ArrowLeft", true, SPAN)).toBeCloseTo(0.15);
    expect(nudge(0.2, "Home", false, SPAN)).toBe(-0.1);
    expect(nudge(0.2, "End", false, SPAN)).toBe(0.9);
    expect(nudge(0.89, "ArrowRight", true, SPAN)).toBe(0.9); // never off the capture
    expect(nudge(0.2, "a", false, SPAN)).toBeNull(); // other keys stay the page's
  });

  it("a typed time is a number within the capture, or says what to type", () => {
    expect(parseCursor("0.25", SPAN)).toBe(0.25);
    expect(parseCursor("0,25", SPAN)).toBe(0.25);
    expect(parseCursor("", SPAN)).toBe("Type a time in seconds");
    expect(parseCursor("abc", SPAN)).toBe("Type a time in seconds");
    expect(parseCursor("3", SPAN)).toBe("From -0.1 to 0.9 s");
  });
});

describe("readout", () => {
  it("shows Δt the way people read it", () => {
    expect(formatDuration(0.25)).toBe("250 ms");
    expect(formatDuration(-0.02)).toBe("-20 ms");
    expect(formatDuration(1.5)).toBe("1.5 s");
    expect(formatDuration(0.0008)).toBe("800 µs");
    expect(formatDuration(0)).toBe("0 s");
  });

  it("has one row per signal, a dash where there is no sample", () => {
    const measurement: Measurement = {
      t0: 0,
      t1: 0.5,
      dt: 0.5,
      start: -0.1,
      end: 0.9,
      signals: [
        {
          node: 1,
          index: 0x606c,
          subindex: 0,
          name: "Velocity actual value",
          unit: "rpm",
          at_a: 0,
          at_b: 299.99999,
          delta: 299.99999,
          min: -1.25,
          max: 300.5,
          mean: 150.123456789,
          count: 501,
        },
        {
          node: 2,
          index: 0x6041,
          subindex: 0,
          name: "Statusword",
          unit: "",
          at_a: null,
          at_b: 1591,
          delta: null,
          min: null,
          max: null,
          mean: null,
          count: 0,
        },
      ],
    };
    const [velocity, status] = readoutRows(measurement);
    expect(velocity).toMatchObject({
      signal: "node 1 Velocity actual value",
      unit: "rpm",
      a: "0",
      b: "300",
      delta: "300",
      min: "-1.25",
      max: "300.5",
      mean: "150.123",
      count: "501",
    });
    // a bit-field word reads in hex (1591 = 0x0637), with no difference or mean
    expect(status).toMatchObject({ a: "—", b: "0x0637", delta: "—", mean: "—", count: "0" });
    expect(formatNumber(1.5e-7)).toBe("1.5000e-7");
  });
});

describe("overview", () => {
  it("draws the min/max bins as one closed band, the highest at the top", () => {
    const path = envelopePath(
      { times: [0, 0.5], low: [0, 10], high: [2, 10] },
      { start: 0, end: 1 },
      100,
      24,
      2,
    );
    expect(path.startsWith("M0,18L50,18")).toBe(true); // bin 1's high (2 of 0…10)
    expect(path).toContain("L50,2L100,2"); // bin 2 at the top
    expect(path.endsWith("Z")).toBe(true);
    expect(envelopePath({ times: [], low: [], high: [] }, { start: 0, end: 1 }, 100, 24)).toBe("");
  });
});

describe("word lanes", () => {
  it("toggle bits in order, and read back what was stored", () => {
    expect(toggleBit([3, 10], 7)).toEqual([3, 7, 10]);
    expect(toggleBit([3, 7, 10], 7)).toEqual([3, 10]);
    expect(parseLanes(JSON.stringify({ statusword_bits: [13, 10, 99, "x"] }))).toEqual({
      statusword_bits: [10, 13],
      controlword_bits: DEFAULT_LANES.controlword_bits,
    });
    expect(parseLanes("{broken")).toEqual(DEFAULT_LANES);
  });

  it("are offered when a statusword or controlword will be captured", () => {
    expect(hasWord([0x6064], "none")).toBe(false);
    expect(hasWord([0x6064, 0x6041], "none")).toBe(true);
    expect(hasWord([0x6040], "none")).toBe(true);
    expect(hasWord([0x6064], "state")).toBe(true); // the trigger adds 6041h
  });
});
