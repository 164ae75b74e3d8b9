// Short names for the commissioning schemas (generated from the backend's OpenAPI): the
// Commission tab's, and those the Network page's node list shares.
import type { components } from "./schema";

type Schemas = components["schemas"];

export type CommissioningRecord = Schemas["CommissioningRecord"];
export type CommissioningStep = Schemas["CommissioningStep"];
export type RecordStatus = CommissioningRecord["status"];
export type StepStatus = CommissioningStep["status"];
export type StepKey = CommissioningStep["key"];
export type StepRun = Schemas["StepRun"];
export type ReportFormat = "html" | "pdf" | "zip";
