import { describe, expect, it } from "vitest";

import { parseForm } from "./formStore";
import { DEFAULT_FORM } from "./model";

describe("parseForm", () => {
  it("brings a stored form back", () => {
    const form = {
      ...DEFAULT_FORM,
      signals: [{ node: 1, index: 0x6064, subindex: 0, name: "Position actual value" }],
      durationS: "2",
      trigger: { ...DEFAULT_FORM.trigger, kind: "level", signal: "1:24676:0", level: "5" },
    };
    expect(parseForm(JSON.stringify(form))).toEqual(form);
  });

  it("falls back to the defaults for what it cannot read", () => {
    expect(parseForm(null)).toEqual(DEFAULT_FORM);
    expect(parseForm("{not json")).toEqual(DEFAULT_FORM);
    const odd = parseForm(
      JSON.stringify({ signals: [{ node: "1" }, 5], syncPeriodUs: 7, trigger: { kind: "x" } }),
    );
    expect(odd.signals).toEqual([]);
    expect(odd.syncPeriodUs).toBe("1000");
    expect(odd.trigger.kind).toBe("none");
  });
});
