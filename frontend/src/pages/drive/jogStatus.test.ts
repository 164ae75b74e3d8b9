import { describe, expect, it } from "vitest";

import { jogStatus } from "./jogStatus";
import type { JogInfo } from "./types";

function jog(state: JogInfo["state"], stop_reason: string | null = null): JogInfo {
  return {
    jog_id: "j1",
    node: 3,
    mode: "pt",
    value: 2,
    keepalive_ms: 300,
    state,
    stop_reason,
  };
}

describe("jogStatus", () => {
  it.each([
    // phase, velocity, last jog, words, stopping, reason
    ["running", 400, null, "Moving — release to stop", false, null],
    ["starting", 0, null, "Starting…", false, null],
    // released at 462 rpm: the axis still runs, whatever the hold says
    [
      "idle",
      462,
      jog("stopped", "stopped by the user"),
      "Stopping — the axis is still moving",
      true,
      null,
    ],
    [
      "idle",
      0,
      jog("stopping", "stopped by the user"),
      "Stopping — the axis is still moving",
      true,
      null,
    ],
    ["idle", -231, null, "Stopping — the axis is still moving", true, null],
    ["idle", 3, jog("stopped", "stopped by the user"), "Stopped", false, null],
    ["idle", 0, null, "Stopped", false, null],
    // a stop the user did not make keeps its reason on the page
    [
      "idle",
      0,
      jog("stopped", "EMCY 8613h from the drive"),
      "Stopped",
      false,
      "EMCY 8613h from the drive",
    ],
    [
      "idle",
      120,
      jog("stopping", "keep-alive missed for 300 ms"),
      "Stopping — the axis is still moving",
      true,
      "keep-alive missed for 300 ms",
    ],
  ] as const)("%s at %s rpm → %s", (phase, rpm, last, text, stopping, reason) => {
    expect(jogStatus(phase, rpm, last)).toEqual({ text, stopping, reason });
  });
});
