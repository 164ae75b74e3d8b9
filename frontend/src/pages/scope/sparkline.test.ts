import { describe, expect, it } from "vitest";

import { capture } from "./fixtures";
import { EMPTY_HISTORY, pushHistory, sparklinePath } from "./sparkline";

describe("sparklinePath", () => {
  it("draws nothing without values, a stub for one", () => {
    expect(sparklinePath([], 100, 20)).toBe("");
    expect(sparklinePath([5], 100, 20)).toBe("M99,10H100");
  });

  it("spreads the values over the width, the lowest at the bottom", () => {
    expect(sparklinePath([0, 10, 5], 100, 24, { pad: 2 })).toBe("M0,22L50,2L100,12");
  });

  it("draws a flat series through the middle", () => {
    expect(sparklinePath([3, 3, 3], 10, 20)).toBe("M0,10L5,10L10,10");
  });

  it("grows from the right when the width holds more values than there are", () => {
    expect(sparklinePath([1, 2], 100, 10, { pad: 0, capacity: 5 })).toBe("M75,10L100,0");
  });
});

describe("pushHistory", () => {
  it("appends each signal's latest value and keeps the last ones", () => {
    let history = pushHistory(EMPTY_HISTORY, capture(), 3);
    expect(history.capture).toBe(7);
    expect(history.values["1:24676:0"]).toEqual([2.5]);
    for (const value of [3, 4, 5]) {
      const next = capture();
      next.signals = next.signals.map((s) => ({ ...s, last_value: value }));
      history = pushHistory(history, next, 3);
    }
    expect(history.values["1:24676:0"]).toEqual([3, 4, 5]);
  });

  it("skips a missing value and starts over for another capture", () => {
    const waiting = capture();
    waiting.signals = waiting.signals.map((s) => ({ ...s, last_value: null }));
    const history = pushHistory(pushHistory(EMPTY_HISTORY, capture()), waiting);
    expect(history.values["1:24684:0"]).toEqual([120]);
    expect(pushHistory(history, capture({ id: 8 })).values["1:24684:0"]).toEqual([120]);
    expect(pushHistory(history, capture({ id: 8 })).capture).toBe(8);
  });
});
