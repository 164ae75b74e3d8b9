// The PDO routes, one function each, through the generated client. Errors come back as
// ApiError (ErrorText shows them); an apply the device refused comes back as data, because
// the page shows its step, abort code and whether the device was restored.
import { api, call } from "../../api/client";
import { asApiError, toApiError } from "../../api/errors";
import type {
  ApplyFailure,
  BusLoad,
  LiveCapture,
  LoadSettings,
  Pdo,
  PdoRules,
  Problem,
  Validation,
} from "./types";

const path = (node: number): { path: { node: number } } => ({ path: { node } });

/** The bus-load settings as the server's query: it compares against the threshold itself. */
function loadQuery(settings: LoadSettings): { threshold: number; master_period_ms: number } {
  return { threshold: settings.threshold, master_period_ms: settings.masterPeriodMs };
}

export function listPdos(node: number, signal?: AbortSignal): Promise<Pdo[]> {
  return call(api.GET("/api/nodes/{node}/pdos", { params: path(node), signal }));
}

/** Where SYNC comes from when neither ServoDesk produces it nor another producer is heard:
 * "external" is the machine's controller (it acknowledges the SYNC warnings). */
export type SyncSource = "external" | null;

export function validatePdos(
  node: number,
  pdos: Pdo[],
  settings: LoadSettings,
  syncSource: SyncSource = null,
  signal?: AbortSignal,
): Promise<Validation> {
  return call(
    api.POST("/api/nodes/{node}/pdos/validate", {
      params: { ...path(node), query: loadQuery(settings) },
      body: { pdos, sync_source: syncSource },
      signal,
    }),
  );
}

export function pdoRules(node: number, signal?: AbortSignal): Promise<PdoRules> {
  return call(api.GET("/api/nodes/{node}/pdos/rules", { params: path(node), signal }));
}

export async function recommendedPdos(node: number, modes: string[]): Promise<Pdo[]> {
  const answer = await call(
    api.GET("/api/nodes/{node}/pdos/recommended", {
      params: { ...path(node), query: { modes: modes.join(",") } },
    }),
  );
  return answer.pdos;
}

export function busLoad(settings: LoadSettings, signal?: AbortSignal): Promise<BusLoad> {
  return call(api.GET("/api/bus-load", { params: { query: loadQuery(settings) }, signal }));
}

export type ApplyOutcome =
  | { result: "applied"; pdos: Pdo[] }
  | { result: "failed"; failure: ApplyFailure }
  | { result: "rejected"; message: string; problems: Problem[] };

export async function applyPdos(
  node: number,
  pdos: Pdo[],
  syncSource: SyncSource = null,
): Promise<ApplyOutcome> {
  let answer;
  try {
    answer = await api.PUT("/api/nodes/{node}/pdos", {
      params: path(node),
      body: { pdos, sync_source: syncSource },
    });
  } catch (error) {
    throw asApiError(error);
  }
  const { data, error, response } = answer;
  if (data) return { result: "applied", pdos: data };
  if (error.error === "pdo_apply_failed") {
    return {
      result: "failed",
      failure: {
        step: error.step ?? "apply",
        abort_code: error.abort_code ?? null,
        message: error.message,
        restored: error.restored ?? false,
      },
    };
  }
  if (error.problems) {
    return { result: "rejected", message: error.message, problems: error.problems };
  }
  throw toApiError(response.status, error, response.statusText);
}

export function startLive(node: number): Promise<LiveCapture> {
  return call(api.POST("/api/nodes/{node}/pdos/live", { params: path(node) }));
}

export function stopLive(node: number): Promise<LiveCapture> {
  return call(api.DELETE("/api/nodes/{node}/pdos/live", { params: path(node) }));
}

export function readLive(node: number, signal?: AbortSignal): Promise<LiveCapture> {
  return call(api.GET("/api/nodes/{node}/pdos/live", { params: path(node), signal }));
}

export type ExportFormat = "dcf" | "python";

export function exportPdos(node: number, format: ExportFormat): Promise<string> {
  return call(
    api.GET("/api/nodes/{node}/pdos/export", {
      params: { ...path(node), query: { format } },
      parseAs: "text",
    }),
  );
}
