import { describe, expect, it } from "vitest";

import { plain } from "./steps";

describe("plain", () => {
  const stamp = 1_795_780_208.9;
  it.each([
    ["at", stamp, new Date(stamp * 1000).toLocaleTimeString()],
    ["sent_at", stamp, new Date(stamp * 1000).toLocaleTimeString()],
    ["stop_time_s", 0.19961, "0.1996"],
    ["modes", ["pp", "pv"], "pp, pv"],
    ["missing", [], "—"],
    ["applied", true, "yes"],
    ["coverage", { mode: "pv", missing: [] }, "mode: pv, missing: —"],
  ])("%s", (key, value, text) => {
    expect(plain(value, key)).toBe(text);
  });
});
