import { describe, expect, it } from "vitest";

import { inChinese } from "../../test/inChinese";
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

  // An MDi-S1-C stops at one drive-inhibit input without a fault: the jog still runs, the
  // axis stands. Moving off the switch again reads as moving.
  it.each([
    // phase, velocity, inputs, words
    [
      "running",
      0,
      { positive_limit: true },
      "Held at the positive limit switch (P-OT): the drive refuses this direction — release, then jog the other way",
    ],
    [
      "running",
      2,
      { negative_limit: true, home_switch: false },
      "Held at the negative limit switch (N-OT): the drive refuses this direction — release, then jog the other way",
    ],
    ["running", -60, { positive_limit: true }, "Moving — release to stop"],
    ["running", 0, { home_switch: true }, "Moving — release to stop"],
    ["idle", 0, { positive_limit: true }, "Stopped"],
  ] as const)("%s at %s rpm on %o → %s", (phase, rpm, inputs, text) => {
    expect(jogStatus(phase, rpm, null, inputs)).toEqual({ text, stopping: false, reason: null });
  });
});

describe("jogStatus in zh-CN", () => {
  inChinese();

  it("says why the jog stopped in Chinese, a reason that adds to another one too", () => {
    const last: JogInfo = {
      ...jog("stopped", "keep-alive missed for 300 ms; the stop could not be sent: …"),
      stop_reason_id: "stop.then_not_sent",
      stop_reason_params: {
        reason: "keep-alive missed for 300 ms",
        reason_id: "stop.keepalive",
        reason_ms: 300,
      },
    };
    expect(jogStatus("idle", 0, last).reason).toBe(
      "300 ms 内未收到保活信号；停止命令无法发送：驱动器的心跳消费者是最后保障，请确认轴已停住",
    );
  });

  it("names the bus state and the drive command in Chinese", () => {
    const bus: JogInfo = {
      ...jog("stopped", "bus disconnected"),
      stop_reason_id: "stop.bus",
      stop_reason_params: { bus_state: "disconnected" },
    };
    expect(jogStatus("idle", 0, bus).reason).toBe("总线未连接");
    const command: JogInfo = {
      ...jog("stopped", "drive command: disable voltage"),
      stop_reason_id: "stop.drive_command",
      stop_reason_params: { drive_command: "disable voltage" },
    };
    expect(jogStatus("idle", 0, command).reason).toBe("驱动器命令：断开电压");
  });

  it("keeps quiet about a stop the user made, by its id", () => {
    const user: JogInfo = {
      ...jog("stopped", "stopped by the user"),
      stop_reason_id: "stop.user",
      stop_reason_params: {},
    };
    expect(jogStatus("idle", 0, user).reason).toBeNull();
  });
});
