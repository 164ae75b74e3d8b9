// Short names for the generated schema types used across pages.
import type { components } from "./schema";

type Schemas = components["schemas"];

export type BusStatus = Schemas["BusStatus"];
export type BusState = Schemas["BusState"];
export type BusConfig = Schemas["BusConfig"];
export type InterfaceInfo = Schemas["InterfaceInfo"];
export type NodeInfo = Schemas["NodeInfo"];
export type NmtStateName = Schemas["NmtStateName"];
export type NmtCommandName = Schemas["NmtCommandName"];
export type ScanResult = Schemas["ScanResult"];
export type LintWarning = Schemas["LintWarningModel"];
export type OdTree = Schemas["OdTree"];
export type OdObject = Schemas["OdObject"];
export type OdEntry = Schemas["OdEntry"];
export type OdCheckResult = Schemas["OdCheckResult"];
export type SdoValue = Schemas["SdoValue"];
export type Job = Schemas["Job"];
export type JobResult = Schemas["JobResult"];
export type Param = Schemas["Param"];
export type ParamWriteResult = Schemas["ParamWriteResult"];
export type NodeIdChangeResult = Schemas["NodeIdChangeResult"];
export type BitrateChangeResult = Schemas["BitrateChangeResult"];
export type DcfLoadResult = Schemas["DcfLoadResult"];
export type CompareRow = Schemas["CompareRow"];
export type CompareResult = Schemas["CompareResult"];
export type BitrateOptions = Schemas["BitrateOptions"];
export type IdentityCheck = Schemas["IdentityCheck"];

/** A value as the API carries it: numbers for numeric types, strings otherwise. */
export type OdValue = number | string | null;
