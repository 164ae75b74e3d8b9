// The motion routes, one function each, through the generated client (the Drive tab's, and
// those the Commission and Faults tabs and the Network page share). Every call carries this
// tab's X-Client-Id, so the server's safety layer knows who commands the drive. Two refusals
// come back as their own errors because the page answers them in words: a blocked enable (the
// reasons) and a node another tab controls (who holds it).
import { api, call } from "./client";
import { clientHeaders, clientName } from "./clientId";
import type {
  ControllerHolder,
  ControllerInfo,
  DriveCommand,
  DriveState,
  EnableReason,
  HomeRequest,
  HomingMethodInfo,
  IpStreamRequest,
  IpStreamResult,
  JogInfo,
  JogMode,
  MotionLimits,
  MoveRequest,
  QuickStopResult,
} from "./drive";
import { ApiError, toApiError } from "./errors";

export class EnableBlockedError extends ApiError {
  readonly reasons: EnableReason[];
  readonly state: DriveState | null;
  constructor(status: number, message: string, reasons: EnableReason[], state: DriveState | null) {
    super(status, "error", message, null);
    this.name = "EnableBlockedError";
    this.reasons = reasons;
    this.state = state;
  }
}

export class HeldByOtherError extends ApiError {
  readonly holder: ControllerHolder | null;
  constructor(
    status: number,
    message: string,
    holder: ControllerHolder | null,
    said: ApiError["said"] = null,
  ) {
    super(status, "error", message, null, null, null, said);
    this.name = "HeldByOtherError";
    this.holder = holder;
  }
}

function isRecord(value: unknown): value is Record<string, unknown> {
  return typeof value === "object" && value !== null && !Array.isArray(value);
}

/** The error a refused motion request stands for. */
export function motionError(status: number, body: unknown, statusText = ""): ApiError {
  if (isRecord(body) && body.error === "enable_blocked") {
    const reasons = Array.isArray(body.reasons)
      ? body.reasons.filter(isRecord).map(
          (r): EnableReason =>
            ({
              code: typeof r.code === "string" ? r.code : "not_ready",
              message: typeof r.message === "string" ? r.message : "",
              message_id: typeof r.message_id === "string" ? r.message_id : null,
              params: isRecord(r.params) ? (r.params as Record<string, string | number>) : {},
            }) as EnableReason,
        )
      : [];
    const state = isRecord(body.state) ? (body.state as unknown as DriveState) : null;
    const message = typeof body.message === "string" ? body.message : "The drive does not enable";
    return new EnableBlockedError(status, message, reasons, state);
  }
  if (isRecord(body) && body.error === "held_by_other") {
    const holder = isRecord(body.holder) ? (body.holder as unknown as ControllerHolder) : null;
    const message =
      typeof body.message === "string" ? body.message : "Another client controls this node";
    const said =
      typeof body.message_id === "string" && isRecord(body.params)
        ? { message_id: body.message_id, params: body.params as Record<string, string | number> }
        : null;
    return new HeldByOtherError(status, message, holder, said);
  }
  return toApiError(status, body, statusText);
}

/** Like the app's `call`, with the motion routes' refusals as their own errors. */
function motionCall<T>(
  request: Promise<{ data?: T; error?: unknown; response: Response }>,
): Promise<T> {
  return call(request, motionError);
}

const on = (node: number): { path: { node: number } } => ({ path: { node } });

export function getDrive(node: number, signal?: AbortSignal): Promise<DriveState> {
  return motionCall(
    api.GET("/api/nodes/{node}/drive", { params: on(node), signal, headers: clientHeaders() }),
  );
}

export type DriveAction = "enable" | "disable" | "quick-stop" | "fault-reset";

export function driveAction(node: number, action: DriveAction): Promise<DriveState> {
  const options = { params: on(node), headers: clientHeaders() };
  switch (action) {
    case "enable":
      return motionCall(api.POST("/api/nodes/{node}/drive/enable", options));
    case "disable":
      return motionCall(api.POST("/api/nodes/{node}/drive/disable", options));
    case "quick-stop":
      return motionCall(api.POST("/api/nodes/{node}/drive/quick-stop", options));
    case "fault-reset":
      return motionCall(api.POST("/api/nodes/{node}/drive/fault-reset", options));
  }
}

export function quickStopAll(): Promise<QuickStopResult> {
  return motionCall(api.POST("/api/quick-stop", { headers: clientHeaders() }));
}

/**
 * One state-machine command (shutdown, switch on, enable operation, disable operation, disable
 * voltage, quick stop, fault reset): the server writes its controlword, waits for the
 * transition and, when it does not happen, answers why (EnableBlockedError).
 */
export function driveCommand(node: number, command: DriveCommand): Promise<DriveState> {
  return motionCall(
    api.POST("/api/nodes/{node}/drive/command", {
      params: on(node),
      body: { command },
      headers: clientHeaders(),
    }),
  );
}

export function move(node: number, body: MoveRequest): Promise<DriveState> {
  return motionCall(
    api.POST("/api/nodes/{node}/drive/move", { params: on(node), body, headers: clientHeaders() }),
  );
}

export function moveQueue(node: number, moves: MoveRequest[]): Promise<DriveState> {
  return motionCall(
    api.POST("/api/nodes/{node}/drive/move-queue", {
      params: on(node),
      body: { moves },
      headers: clientHeaders(),
    }),
  );
}

export function home(node: number, body: HomeRequest): Promise<DriveState> {
  return motionCall(
    api.POST("/api/nodes/{node}/drive/home", { params: on(node), body, headers: clientHeaders() }),
  );
}

export function homingMethods(node: number, signal?: AbortSignal): Promise<HomingMethodInfo[]> {
  return motionCall(
    api.GET("/api/nodes/{node}/drive/homing-methods", { params: on(node), signal }),
  );
}

export function putLimits(node: number, limits: MotionLimits): Promise<MotionLimits> {
  return motionCall(
    api.PUT("/api/nodes/{node}/drive/limits", {
      params: on(node),
      body: limits,
      headers: clientHeaders(),
    }),
  );
}

export function ipStream(node: number, body: IpStreamRequest): Promise<IpStreamResult> {
  return motionCall(
    api.POST("/api/nodes/{node}/drive/ip-stream", {
      params: on(node),
      body,
      headers: clientHeaders(),
    }),
  );
}

export function getController(node: number, signal?: AbortSignal): Promise<ControllerInfo> {
  return motionCall(
    api.GET("/api/nodes/{node}/drive/controller", {
      params: on(node),
      signal,
      headers: clientHeaders(),
    }),
  );
}

export function takeControl(node: number, takeOver: boolean): Promise<ControllerInfo> {
  return motionCall(
    api.POST("/api/nodes/{node}/drive/controller", {
      params: on(node),
      body: { take_over: takeOver, name: clientName() },
      headers: clientHeaders(),
    }),
  );
}

/** How a jog ramps: PV's acceleration (6083h/6084h), PT's torque slope (6087h). */
export interface JogRamp {
  accelerationRpmS?: number | null;
  torqueSlopePctS?: number | null;
  /** PT: ServoDesk's own speed cap; the jog is stopped when the axis passes it. */
  speedCapRpm?: number | null;
}

export function startJog(
  node: number,
  mode: JogMode,
  value: number,
  keepaliveMs: number,
  ramp: JogRamp = {},
): Promise<JogInfo> {
  const body =
    mode === "pv"
      ? {
          mode,
          velocity_rpm: value,
          keepalive_ms: keepaliveMs,
          acceleration_rpm_s: ramp.accelerationRpmS ?? null,
        }
      : {
          mode,
          torque_pct: value,
          keepalive_ms: keepaliveMs,
          torque_slope_pct_s: ramp.torqueSlopePctS ?? null,
          speed_cap_rpm: ramp.speedCapRpm ?? null,
        };
  return motionCall(
    api.POST("/api/nodes/{node}/jog", { params: on(node), body, headers: clientHeaders() }),
  );
}

export async function jogKeepalive(jogId: string): Promise<void> {
  await motionCall(
    api.POST("/api/jog/{jog_id}/keepalive", {
      params: { path: { jog_id: jogId } },
      headers: clientHeaders(),
    }),
  );
}

export async function stopJog(jogId: string): Promise<void> {
  await motionCall(
    api.DELETE("/api/jog/{jog_id}", {
      params: { path: { jog_id: jogId } },
      headers: clientHeaders(),
    }),
  );
}
