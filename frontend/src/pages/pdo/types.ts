// The PDO API's shapes, from the generated schema (never edited by hand).
import type { components } from "../../api/schema";

type Schemas = components["schemas"];

export type Pdo = Schemas["Pdo"];
export type PdoKind = Pdo["kind"];
export type MappedObject = Schemas["PdoMappedObject"];
/** A problem names its PDO and, when it is about one object, that object (mapped object, or
 * the communication / mapping parameter entry). */
export type Problem = Schemas["PdoProblem"];
export type PdoLoad = Schemas["PdoLoadModel"];
export type NodeLoad = Schemas["NodeLoadModel"];
export type BusLoad = Schemas["BusLoadResult"];
export type Validation = Schemas["PdoValidation"];
/** A decoded value: `raw` is the field's bytes as hex pairs ("50 02"), `text` the value in
 * words when it has some (Statusword state, mode name). */
export type LiveValue = Schemas["LiveValue"];
/** `rate_hz` is null until two frames have arrived. */
export type LivePdo = Schemas["LivePdo"];
export type LiveCapture = Schemas["LiveCheck"];
export type ErrorBody = Schemas["ErrorBody"];
/** How the node takes PDOs: byte granularity, fixed CAN ids (PDOs 1..fixed_cob_ids), RTR
 * support, counts, and the procedure of an apply in words. */
export type PdoRules = Schemas["PdoRules"];

/** The bus-load settings the server computes with. */
export interface LoadSettings {
  /** Percent above which the load is too high. */
  threshold: number;
  /** The assumed period at which the master sends event-driven RPDOs. */
  masterPeriodMs: number;
}

/** The 409 of an apply the device refused part-way. */
export interface ApplyFailure {
  step: string;
  abort_code: string | null;
  message: string;
  restored: boolean;
}
