// Short names for the motion API's generated types (backend servodesk/motion/schemas.py and
// safety_models.py): the Drive tab's, and those live/ and other pages share.
import type { components } from "./schema";

type Schemas = components["schemas"];

/** As the client hands it over: openapi-fetch reads the gear-ratio tuple as an array. */
export type DriveState = Omit<Schemas["DriveState"], "gear_ratio"> & {
  gear_ratio: number[] | null;
};
export type DriveStateName = Schemas["DriveState"]["state"];
export type StatusBit = Schemas["StatusBit"];
export type FaultInfo = Schemas["FaultInfo"];
export type MotionLimits = Schemas["MotionLimits"];
export type HomingProgress = Schemas["HomingProgress"];
export type HomingPhase = HomingProgress["phase"];
export type MoveProgress = Schemas["MoveProgress"];
export type EnableReason = Schemas["EnableReason"];
export type PathStep = Schemas["PathStep"];
export type HomingMethodInfo = Schemas["HomingMethodInfo"];
export type ControllerHolder = Schemas["ControllerHolder"];
export type HeartbeatProtection = Schemas["HeartbeatProtection"];
export type ControllerInfo = Schemas["ControllerInfo"];
export type MoveRequest = Schemas["MoveRequest"];
export type HomeRequest = Schemas["HomeRequest"];
export type IpStreamRequest = Schemas["IpStreamRequest"];
export type IpTrajectory = IpStreamRequest["trajectory"];
export type IpStreamResult = Omit<Schemas["IpStreamResult"], "state"> & { state: DriveState };
export type JogInfo = Schemas["JogInfo"];
export type JogMode = Schemas["JogRequest"]["mode"];
export type DriveCommand = Schemas["DriveCommandRequest"]["command"];
export type QuickStopResult = Schemas["QuickStopResult"];
export type MotionErrorBody = Schemas["MotionErrorBody"];
export type DriveLimits = Schemas["DriveLimits"];
export type TravelEnds = Schemas["TravelEnds"];
export type TravelInfo = Schemas["TravelInfo"];
