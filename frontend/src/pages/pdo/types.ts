// The PDO API's shapes, from the generated schema (never edited by hand).
import type { components } from "../../api/schema";

type Schemas = components["schemas"];

export type Pdo = Schemas["Pdo"];
export type PdoKind = Pdo["kind"];
export type MappedObject = Schemas["PdoMappedObject"];
/** A problem names its PDO; the contract lets it name the object too (index, subindex). */
export type Problem = Schemas["PdoProblem"] & { index?: number | null; subindex?: number | null };
export type PdoLoad = Schemas["PdoLoadModel"];
export type NodeLoad = Schemas["NodeLoadModel"];
export type BusLoad = Schemas["BusLoadResult"];
export type Validation = Schemas["PdoValidation"];
export type LiveValue = Schemas["LiveValue"];
export type LivePdo = Schemas["LivePdo"];
export type LiveCapture = Schemas["LiveCheck"];
export type ErrorBody = Schemas["ErrorBody"];

/** The 409 of an apply the device refused part-way. */
export interface ApplyFailure {
  step: string;
  abort_code: string | null;
  message: string;
  restored: boolean;
}
