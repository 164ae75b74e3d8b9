// The commissioning routes (docs/api.md, "Commissioning"), one function each: the Commission
// tab's, and the record list the Network page's node list reads. A step run that finds the axis
// held by another client comes back as HeldByOtherError, which names the holder.
import type { Language } from "../i18n";
import { api, call } from "./client";
import type {
  CommissioningRecord,
  CommissioningStep,
  ReportFormat,
  StepKey,
  StepRun,
} from "./commission";
import { motionError } from "./driveApi";

/** The node's records, newest first; without a node, every node's. */
export function listRecords(
  node: number | null,
  signal?: AbortSignal,
): Promise<CommissioningRecord[]> {
  const query = node === null ? {} : { node };
  return call(api.GET("/api/commissioning", { params: { query }, signal }));
}

export function getRecord(id: number, signal?: AbortSignal): Promise<CommissioningRecord> {
  return call(
    api.GET("/api/commissioning/{record_id}", { params: { path: { record_id: id } }, signal }),
  );
}

export function createRecord(
  node: number,
  modes: string[],
  title: string,
): Promise<CommissioningRecord> {
  const body = title.trim() ? { modes, title: title.trim() } : { modes };
  return call(api.POST("/api/nodes/{node}/commissioning", { params: { path: { node } }, body }));
}

export function signOffStep(
  id: number,
  key: StepKey,
  status: "done" | "skipped",
  reason?: string,
): Promise<CommissioningStep> {
  const body = reason ? { status, reason } : { status };
  return call(
    api.PUT("/api/commissioning/{record_id}/steps/{key}", {
      params: { path: { record_id: id, key } },
      body,
    }),
  );
}

/** Runs the step's automated part; takes seconds (the moving steps and store_verify). */
export function runStep(id: number, key: StepKey, body: StepRun = {}): Promise<CommissioningStep> {
  return call(
    api.POST("/api/commissioning/{record_id}/steps/{key}/run", {
      params: { path: { record_id: id, key } },
      body,
    }),
    motionError,
  );
}

/** The report route as a plain link (the browser opens or downloads it), its own words in
 * `lang` (the records' data stays as stored). */
export function reportUrl(id: number, format: ReportFormat, lang: Language): string {
  return `/api/commissioning/${id}/report?format=${format}&lang=${lang}`;
}
