// The scope routes, one function each, through the generated client. Errors come back as
// ApiError (ErrorText shows them).
import { api, call } from "../../api/client";
import { asApiError, toApiError } from "../../api/errors";
import type { OdTree } from "../../api/types";
import type {
  Capture,
  CaptureRequest,
  ExportFormat,
  ExportLayout,
  Measurement,
  ScopePlan,
  ScopeViewer,
  Trace,
} from "./types";

/** What the capture would do (sources, bus load), without starting it. */
export function planCapture(request: CaptureRequest, signal?: AbortSignal): Promise<ScopePlan> {
  return call(api.POST("/api/scope/plan", { body: request, signal }));
}

export function startCapture(request: CaptureRequest): Promise<Capture> {
  return call(api.POST("/api/scope/captures", { body: request }));
}

export function getCapture(id: number, signal?: AbortSignal): Promise<Capture> {
  return call(
    api.GET("/api/scope/captures/{capture_id}", { params: { path: { capture_id: id } }, signal }),
  );
}

/** Every capture kept, newest first. */
export function listCaptures(signal?: AbortSignal): Promise<Capture[]> {
  return call(api.GET("/api/scope/captures", { signal }));
}

/** Stop an armed or running capture (the capture as kept), or delete a finished one (null). */
export async function stopOrDeleteCapture(id: number): Promise<Capture | null> {
  let answer;
  try {
    answer = await api.DELETE("/api/scope/captures/{capture_id}", {
      params: { path: { capture_id: id } },
    });
  } catch (error) {
    throw asApiError(error);
  }
  const { data, error, response } = answer;
  if (response.status === 204) return null;
  if (!response.ok || !data) throw toApiError(response.status, error, response.statusText);
  return data;
}

/** Where the embedded rerun viewer is (the app starts it on this call). */
export function scopeViewer(signal?: AbortSignal): Promise<ScopeViewer> {
  return call(api.GET("/api/scope/viewer", { signal }));
}

/** The node's object dictionary, as the OD page lists it. */
export function nodeDictionary(node: number, signal?: AbortSignal): Promise<OdTree> {
  return call(api.GET("/api/nodes/{node}/od", { params: { path: { node } }, signal }));
}

/** A plain link: the browser downloads the export itself. CSV `wide`: one row per time stamp,
 * a column per signal (the default, long: one row per sample). */
export function exportUrl(id: number, format: ExportFormat, layout?: ExportLayout): string {
  const wide = layout === "wide" ? "&layout=wide" : "";
  return `/api/scope/captures/${id}/export?format=${format}${wide}`;
}

/** The capture's rerun recording (.rrd) as bytes, for the embedded viewer. */
export async function fetchRrd(id: number, signal?: AbortSignal): Promise<Uint8Array> {
  const data = await call(
    api.GET("/api/scope/captures/{capture_id}/export", {
      params: { path: { capture_id: id }, query: { format: "rrd" } },
      parseAs: "arrayBuffer",
      signal,
    }),
  );
  return new Uint8Array(data);
}

/** The readout between cursor A (`t0`) and B (`t1`), s from the trigger. */
export function measureCapture(
  id: number,
  t0: number,
  t1: number,
  signal?: AbortSignal,
): Promise<Measurement> {
  return call(
    api.GET("/api/scope/captures/{capture_id}/measure", {
      params: { path: { capture_id: id }, query: { t0, t1 } },
      signal,
    }),
  );
}

/** One signal of a finished capture reduced to `points` min/max bins. */
export function traceCapture(
  id: number,
  position: number,
  points: number,
  signal?: AbortSignal,
): Promise<Trace> {
  return call(
    api.GET("/api/scope/captures/{capture_id}/trace", {
      params: { path: { capture_id: id }, query: { signal: position, points } },
      signal,
    }),
  );
}
