// Short names for the fault schemas (generated from the backend's OpenAPI): the Faults tab's,
// and those live/ and the fault banner share.
import type { components } from "./schema";

type Schemas = components["schemas"];

/** One decoded EMCY: the drive's own alarm table first, then CiA 402, CiA 301, the class. */
export type Fault = Schemas["Fault"];
export type NodeFaults = Schemas["NodeFaults"];
export type ActiveFaults = Schemas["ActiveFaults"];
export type FaultResetResult = Schemas["FaultResetResult"];
/** 1003h decoded, newest first, with 603Fh. */
export type DeviceHistory = Schemas["DeviceHistory"];
export type DeviceHistoryEntry = Schemas["DeviceHistoryEntry"];
export type DeviceHistoryCleared = Schemas["DeviceHistoryCleared"];
