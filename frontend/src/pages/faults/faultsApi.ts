// The fault routes, one function each. Errors come back as ApiError (ErrorText shows them).
import { api, call, odPath } from "../../api/client";
import type { SdoValue } from "../../api/types";
import type {
  ActiveFaults,
  DeviceHistory,
  DeviceHistoryCleared,
  FaultResetResult,
  NodeFaults,
} from "./types";

const path = (node: number): { path: { node: number } } => ({ path: { node } });

export function nodeFaults(node: number, signal?: AbortSignal): Promise<NodeFaults> {
  return call(api.GET("/api/nodes/{node}/faults", { params: path(node), signal }));
}

export function activeFaults(signal?: AbortSignal): Promise<ActiveFaults> {
  return call(api.GET("/api/faults/active", { signal }));
}

export function resetFault(node: number): Promise<FaultResetResult> {
  return call(api.POST("/api/nodes/{node}/faults/reset", { params: path(node) }));
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
