// The scope API's shapes, from the generated schema (never edited by hand).
import type { components } from "../../api/schema";

type Schemas = components["schemas"];

export type CaptureRequest = Schemas["CaptureRequest"];
export type TriggerRequest = Schemas["TriggerRequest"];
export type TriggerKind = TriggerRequest["kind"];
export type Edge = TriggerRequest["edge"];
export type TriggerMode = TriggerRequest["mode"];
/** A signal as the scope will carry it: `source` pdo (with `tpdo`, `cob_id`) or sdo (with
 * `note`, why), its units, and while recording its sample count, rate and latest value. */
export type CaptureSignal = Schemas["CaptureSignal"];
export type Capture = Schemas["Capture"];
export type CaptureState = Capture["state"];
export type ScopePlan = Schemas["ScopePlan"];
export type ScopeViewer = Schemas["ScopeViewer"];
export type BusLoad = Schemas["BusLoadResult"];
/** Which statusword / controlword bits get a lane of their own in the recording. */
export type LanesRequest = Schemas["LanesRequest"];
/** Two cursors on a finished capture and, per signal, what lies at and between them. */
export type Measurement = Schemas["Measurement"];
export type SignalMeasurement = Schemas["SignalMeasurement"];
/** One signal of a finished capture as min/max bins, for the cursors' overview plot. */
export type Trace = Schemas["Trace"];

/** The export formats of a finished capture. */
export type ExportFormat = "csv" | "parquet" | "mf4" | "rrd";
/** CSV rows: one per sample (long, the default) or one per time stamp (wide). */
export type ExportLayout = "long" | "wide";
