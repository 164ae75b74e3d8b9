import { describe, expect, it } from "vitest";

import { lagWords } from "./LoopLag";

describe("lagWords", () => {
  it.each([
    // p50, p99, max, busy
    [0.8, 4.2, 12, false],
    [1, 20, 100, false], // on the targets
    [1, 21, 40, true], // p99 over 20 ms
    [1, 8, 140, true], // one stall over 100 ms
  ])("p50 %s, p99 %s, max %s → busy %s", (p50, p99, max, busy) => {
    const words = lagWords({ p50_ms: p50, p99_ms: p99, max_ms: max, samples: 1200, window_s: 60 });
    expect(words.busy).toBe(busy);
    expect(words.text).toContain(`p99 ${p99.toFixed(1)} ms`);
    expect(words.text.includes("the server was busy")).toBe(busy);
  });
});
