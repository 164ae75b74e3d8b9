import { describe, expect, it } from "vitest";

import { manualFor } from "./manuals";

describe("manualFor", () => {
  it.each([
    ["mdi-s1c", "state_machine", "MDi-S1-C CANopen manual §3.2.1"],
    ["mdi-s1c", "homing", "MDi-S1-C CANopen manual §3.7"],
    ["kinco", "homing", "Kinco servo CANopen manual §5.4.6"],
    ["cia402", "state_machine", "CiA 402 state machine (controlword 6040h, statusword 6041h)"],
    ["cia402", "homing", "CiA 402 homing mode (6098h methods)"],
    [undefined, "homing", "CiA 402 homing mode (6098h methods)"],
  ] as const)("%s %s", (profile, topic, text) => {
    expect(manualFor(profile, topic)).toBe(text);
  });
});
