// Where each drive's own manual describes what a Drive-page card shows; a drive ServoDesk has
// no manual for is pointed at the CiA 402 profile itself (pure, table-tested).

export type DriveTopic = "state_machine" | "homing";

const MANUALS: Record<string, Record<DriveTopic, string>> = {
  "mdi-s1c": {
    state_machine: "MDi-S1-C CANopen manual §3.2.1",
    homing: "MDi-S1-C CANopen manual §3.7",
  },
  kinco: {
    state_machine: "Kinco servo CANopen manual, control word and status word (6040h/6041h)",
    homing: "Kinco servo CANopen manual §5.4.6",
  },
};

const PROFILE: Record<DriveTopic, string> = {
  state_machine: "CiA 402 state machine (controlword 6040h, statusword 6041h)",
  homing: "CiA 402 homing mode (6098h methods)",
};

/** The reference for `topic` on a drive of `profile` (the node's profile name). */
export function manualFor(profile: string | undefined, topic: DriveTopic): string {
  return (profile !== undefined ? MANUALS[profile]?.[topic] : undefined) ?? PROFILE[topic];
}
