// Canned parameters for the Parameters page tests: PA-106 (a choice, after reset) and PA-103
// (a number in rpm, immediately).
import type { Param } from "../../api/types";

export const PA106: Param = {
  name: "PA-106",
  label: "CAN bitrate",
  description: "Bitrate of the CAN interface",
  object: "2006:0B",
  index: 0x2006,
  subindex: 0x0b,
  value: 5,
  unit: "",
  min: 0,
  max: 6,
  default: 5,
  takes_effect: "after_reset",
  choices: { "4": "250 kbit/s", "5": "500 kbit/s" },
  error: null,
  pending: false,
};

export const PA103: Param = {
  ...PA106,
  name: "PA-103",
  label: "Maximum speed",
  object: "2006:08",
  subindex: 8,
  value: 6000,
  unit: "rpm",
  min: 0,
  max: 6000,
  default: 6000,
  takes_effect: "immediately",
  choices: {},
};
