// Fault answers as the server sends them, for the page tests.
import type { Fault } from "./types";

export function mdiAlarm4(overrides: Partial<Fault> = {}): Fault {
  return {
    time: 1_764_000_000.5,
    node: 1,
    code: 4,
    code_hex: "0x0004",
    source: "vendor",
    name_en: "Following error",
    name_zh: "位置超差",
    check:
      "Cause: position deviation above the limit. Check: gain, load, 6065h. CiA code 8611h: Following error. Source: MDi-S1-C CANopen manual §4.1.",
    error_register: null,
    manufacturer_hex: null,
    raw_hex: "04 00",
    state_before: "Switch on disabled",
    state_after: "Fault",
    ...overrides,
  };
}

export function cia402Fault(overrides: Partial<Fault> = {}): Fault {
  return {
    time: 1_764_000_100,
    node: 3,
    code: 0x8611,
    code_hex: "0x8611",
    source: "cia402",
    name_en: "Following error",
    name_zh: null,
    check: "CiA class: Monitoring. Error register 21h: generic, device profile.",
    error_register: 0x21,
    manufacturer_hex: "00 00 00 00 00",
    raw_hex: "11 86 21 00 00 00 00 00",
    state_before: "Operation enabled",
    state_after: "Fault",
    ...overrides,
  };
}
