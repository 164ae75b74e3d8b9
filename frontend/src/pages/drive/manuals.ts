// Where each drive's own manual describes what a Drive-page card shows; a drive ServoDesk has
// no manual for is pointed at the CiA 402 profile itself (pure, table-tested).

import { i18n, type MessageKey } from "../../i18n";

export type DriveTopic = "state_machine" | "homing";

const MANUALS: Record<string, Record<DriveTopic, MessageKey>> = {
  "mdi-s1c": {
    state_machine: "drive.manual.mdiStateMachine",
    homing: "drive.manual.mdiHoming",
  },
  kinco: {
    state_machine: "drive.manual.kincoStateMachine",
    homing: "drive.manual.kincoHoming",
  },
};

const PROFILE: Record<DriveTopic, MessageKey> = {
  state_machine: "drive.manual.stateMachine",
  homing: "drive.manual.homing",
};

/** The reference for `topic` on a drive of `profile` (the node's profile name). */
export function manualFor(profile: string | undefined, topic: DriveTopic): string {
  return i18n.t((profile !== undefined ? MANUALS[profile]?.[topic] : undefined) ?? PROFILE[topic]);
}
