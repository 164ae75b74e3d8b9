import { describe, expect, it } from "vitest";

import { addSample, segments } from "./timeline";

describe("homing timeline", () => {
  it("merges repeats so a long run stays small", () => {
    let samples = addSample([], { t: 0, statusword: 0x0237 });
    samples = addSample(samples, { t: 100, statusword: 0x0237 });
    samples = addSample(samples, { t: 200, statusword: 0x0237 });
    samples = addSample(samples, { t: 300, statusword: 0x1637 });
    expect(samples.map((s) => s.t)).toEqual([0, 200, 300]);
  });

  it.each([
    [12, [[75, 100]]],
    [10, [[75, 100]]],
    [13, []],
  ])("bit %i is on over %j", (bit, expected) => {
    const samples = [
      { t: 0, statusword: 0x0237 },
      { t: 300, statusword: 0x1637 },
    ];
    expect(segments(samples, bit, 100, 400)).toEqual(expected);
  });

  it("joins adjacent on-samples into one segment", () => {
    const samples = [
      { t: 0, statusword: 0x0400 },
      { t: 50, statusword: 0x0400 | 0x1000 },
      { t: 100, statusword: 0 },
    ];
    expect(segments(samples, 10, 200, 200)).toEqual([[0, 100]]);
  });
});
