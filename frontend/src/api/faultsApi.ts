// The fault routes, one function each (the Faults tab's, and the active faults the fault banner
// reads). Errors come back as ApiError (ErrorText shows them).
import { api, call, odPath } from "./client";
import { clientHeaders } from "./clientId";
import { motionError } from "./driveApi";
import { asApiError } from "./errors";
import type {
  ActiveFaults,
  DeviceHistory,
  DeviceHistoryCleared,
  FaultResetResult,
  NodeFaults,
} from "./faults";
import type { SdoValue } from "./types";

const path = (node: number): { path: { node: number } } => ({ path: { node } });

/** Fault history entries per page of GET /api/nodes/{node}/faults (the server's default). */
export const FAULT_HISTORY_PAGE = 100;

/** The node's faults on the connected bus, the newest `limit` of its history; `allBuses`: also
 * those stored from other buses (another server sharing the data directory, a bus connected
 * before). */
export function nodeFaults(
  node: number,
  signal?: AbortSignal,
  { allBuses = false, limit = FAULT_HISTORY_PAGE }: { allBuses?: boolean; limit?: number } = {},
): Promise<NodeFaults> {
  const query = {
    ...(allBuses ? { all_buses: true } : {}),
    ...(limit === FAULT_HISTORY_PAGE ? {} : { limit }),
  };
  return call(api.GET("/api/nodes/{node}/faults", { params: { path: { node }, query }, signal }));
}

export function activeFaults(signal?: AbortSignal): Promise<ActiveFaults> {
  return call(api.GET("/api/faults/active", { signal }));
}

/** As this tab (X-Client-Id): a drive this tab controls is reset; one another tab or client
 * controls is refused as HeldByOtherError, which names the holder. */
export async function resetFault(node: number): Promise<FaultResetResult> {
  let result;
  try {
    result = await api.POST("/api/nodes/{node}/faults/reset", {
      params: path(node),
      headers: clientHeaders(),
    });
  } catch (error) {
    throw asApiError(error);
  }
  const { data, error, response } = result;
  if (!response.ok || data === undefined) {
    throw motionError(response.status, error, response.statusText);
  }
  return data;
}

export function deviceHistory(node: number, signal?: AbortSignal): Promise<DeviceHistory> {
  return call(api.GET("/api/nodes/{node}/faults/device-history", { params: path(node), signal }));
}

export function clearDeviceHistory(node: number): Promise<DeviceHistoryCleared> {
  return call(
    api.DELETE("/api/nodes/{node}/faults/device-history", {
      params: path(node),
      body: { confirm: true },
    }),
  );
}

/** 603Fh, the drive's error code now (0: no error). */
export function errorCode(node: number, signal?: AbortSignal): Promise<SdoValue> {
  return call(
    api.GET("/api/nodes/{node}/sdo/{index}/{subindex}", {
      params: { path: { node, ...odPath(0x603f, 0) } },
      signal,
    }),
  );
}
