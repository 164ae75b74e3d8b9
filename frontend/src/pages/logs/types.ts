// Short names for the log and recording schemas, and the log totals read from the free-form
// `stats` object. The live timeline's are in api/timeline.ts.
import type { components } from "../../api/schema";

type Schemas = components["schemas"];

/** One decoded event of a log file. */
export type LogEvent = Schemas["LogEvent"];
export type LogEventPage = Schemas["LogEventPage"];
/** POST /api/logs/decode: summary, stats and the first page of events. */
export type DecodedLog = Schemas["DecodedLog"];
/** A decoded log kept on the server (GET /api/logs). */
export type KeptLog = Schemas["KeptLogInfo"];
export type RecordingFormat = Schemas["RecordingFormat"];
export type RecordingInfo = Schemas["RecordingInfo"];
export type ExportFormat = Exclude<Schemas["ExportFormat"], "text">;

/** The totals of a decoded log (`stats`), as far as the page shows them. */
export interface LogStats {
  frames: number;
  duration_s: number;
  nodes: number[] | null;
  counts: Record<string, number>;
  error_frames: number;
  bitrate: number | null;
  bus_load_peak_percent: number | null;
  bus_load_mean_percent: number | null;
  events: number | null;
}
