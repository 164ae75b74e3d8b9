import type { components } from "../../api/schema";

type Schemas = components["schemas"];

export type CommissioningRecord = Schemas["CommissioningRecord"];
export type CommissioningStep = Schemas["CommissioningStep"];
export type RecordStatus = CommissioningRecord["status"];
export type StepStatus = CommissioningStep["status"];
export type StepKey = CommissioningStep["key"];
export type StepRun = Schemas["StepRun"];
export type ReportFormat = "html" | "pdf" | "zip";
