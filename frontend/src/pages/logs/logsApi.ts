// The log and recording routes, one function each.
import { api, call } from "../../api/client";
import { asApiError, toApiError } from "../../api/errors";
import type {
  DecodedLog,
  ExportFormat,
  KeptLog,
  LogEventPage,
  RecordingFormat,
  RecordingInfo,
} from "./types";

export const LOG_FILE_TYPES = ".log,.asc,.blf,.trc,.mf4,.csv,.txt";
export const DCF_FILE_TYPES = ".dcf,.eds";

/** `profiles` names nodes' drives for logs without identity reads: "1=mdi-s1c, 2=kinco". */
export function decodeLog(file: File, dcf: File | null, profiles = ""): Promise<DecodedLog> {
  const form = new FormData();
  form.append("file", file, file.name);
  if (dcf) form.append("dcf", dcf, dcf.name);
  if (profiles.trim()) form.append("profiles", profiles.trim());
  // the generated body type names the files as strings; the form carries the Files themselves
  return call(
    api.POST("/api/logs/decode", {
      body: { file: file.name, dcf: dcf?.name ?? null, profiles: profiles.trim() || null },
      bodySerializer: () => form,
    }),
  );
}

/** The decoded logs the server keeps, newest first. */
export function keptLogs(signal?: AbortSignal): Promise<KeptLog[]> {
  return call(api.GET("/api/logs", { signal }));
}

/** A kept log again: summary, totals and the first page of events. */
export function openLog(id: string): Promise<DecodedLog> {
  return call(api.GET("/api/logs/{log_id}", { params: { path: { log_id: id } } }));
}

/** 204 on success: no body, so not through `call` (which wants one). */
export async function deleteLog(id: string): Promise<void> {
  let answer;
  try {
    answer = await api.DELETE("/api/logs/{log_id}", { params: { path: { log_id: id } } });
  } catch (error) {
    throw asApiError(error);
  }
  const { error, response } = answer;
  if (!response.ok) throw toApiError(response.status, error, response.statusText);
}

/** A page of a log's events; `hidePolling` leaves out SDO reads repeated at a steady period. */
export function logEvents(
  id: string,
  since: number,
  limit: number,
  signal?: AbortSignal,
  hidePolling = false,
): Promise<LogEventPage> {
  return call(
    api.GET("/api/logs/{log_id}/events", {
      params: {
        path: { log_id: id },
        query: { since, limit, ...(hidePolling ? { hide_polling: true } : {}) },
      },
      signal,
    }),
  );
}

/** A plain link: the browser downloads the export itself. */
export function exportUrl(id: string, format: ExportFormat): string {
  return `/api/logs/${encodeURIComponent(id)}/export?format=${format}`;
}

export function recordingStatus(signal?: AbortSignal): Promise<RecordingInfo> {
  return call(api.GET("/api/recording", { signal }));
}

export function startRecording(format: RecordingFormat): Promise<RecordingInfo> {
  return call(api.POST("/api/recording", { body: { format } }));
}

/** A stopped recording: the file as the server names it. */
export interface RecordedFile {
  blob: Blob;
  name: string;
}

/** 'attachment; filename="bus.blf"' → "bus.blf"; the fallback without a header. */
export function dispositionName(header: string | null, fallback: string): string {
  const match = header ? /filename\*?=(?:UTF-8'')?"?([^";]+)"?/i.exec(header) : null;
  return match?.[1] ? decodeURIComponent(match[1]) : fallback;
}

export async function stopRecording(fallbackName: string): Promise<RecordedFile> {
  let answer;
  try {
    answer = await api.DELETE("/api/recording", { parseAs: "blob" });
  } catch (error) {
    throw asApiError(error);
  }
  const { data, error, response } = answer;
  if (!response.ok || !data) throw toApiError(response.status, error, response.statusText);
  return {
    blob: data,
    name: dispositionName(response.headers.get("Content-Disposition"), fallbackName),
  };
}

/** Save a blob under a name through the browser's download. */
export function saveBlob(blob: Blob, name: string): void {
  const url = URL.createObjectURL(blob);
  const link = document.createElement("a");
  link.href = url;
  link.download = name;
  link.click();
  setTimeout(() => URL.revokeObjectURL(url), 0);
}
