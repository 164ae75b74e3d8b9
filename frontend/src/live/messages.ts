// Messages on the live WebSocket /api/ws (docs/api.md, "WebSocket"). They are not part of the
// OpenAPI schema, so they are described here and checked on arrival: a malformed message is
// dropped instead of corrupting the store.
import type { ControllerInfo, DriveState, JogInfo } from "../api/drive";
import type { Fault } from "../api/faults";
import type { TimelineEvent } from "../api/timeline";
import type { BusStatus, NmtStateName } from "../api/types";

export interface LiveNode {
  node: number;
  nmt_state: NmtStateName;
  online: boolean;
  heartbeat_age_ms: number | null;
}

export type LiveEventKind = "boot-up" | "node-lost" | "node-back" | "nmt" | "bus";

export interface LiveEvent {
  time: number; // UNIX seconds
  node: number | null;
  kind: LiveEventKind;
  message: string;
  /** The message by id, for the page's language (lib/serverText.ts). */
  message_id?: string | null;
  params?: Record<string, string | number>;
}

export type ServerMessage =
  | { type: "bus"; bus: BusStatus }
  | { type: "nodes"; nodes: LiveNode[] }
  | { type: "event"; event: LiveEvent }
  | { type: "history"; events: LiveEvent[] }
  | { type: "pong" }
  | { type: "timeline"; event: TimelineEvent }
  | { type: "fault"; node: number; fault: Fault | null }
  | { type: "drive_state"; state: DriveState }
  | { type: "controller"; controller: ControllerInfo }
  | { type: "jog_stopped"; jog: JogInfo };

/** What the browser sends (the server's safety layer watches the jog messages like the REST
 * keep-alives: a missing one stops the axis). */
export type ClientMessage =
  | { type: "ping" }
  | { type: "hello"; client_id: string; name: string }
  | { type: "jog_keepalive"; jog_id: string }
  | { type: "jog_stop"; jog_id: string }
  | { type: "page_hidden" }
  | { type: "quick_stop"; node: number | null }
  | { type: "watch_drive"; node: number }
  | { type: "unwatch_drive"; node: number };

const NMT_STATES: ReadonlySet<string> = new Set<NmtStateName>([
  "initialising",
  "pre-operational",
  "operational",
  "stopped",
  "unknown",
]);

function isRecord(value: unknown): value is Record<string, unknown> {
  return typeof value === "object" && value !== null && !Array.isArray(value);
}

function parseNode(value: unknown): LiveNode | null {
  if (!isRecord(value) || typeof value.node !== "number") return null;
  const state = typeof value.nmt_state === "string" ? value.nmt_state : "unknown";
  return {
    node: value.node,
    nmt_state: (NMT_STATES.has(state) ? state : "unknown") as NmtStateName,
    online: value.online === true,
    heartbeat_age_ms: typeof value.heartbeat_age_ms === "number" ? value.heartbeat_age_ms : null,
  };
}

/** An event's words by id, when the server sent them (docs/api.md, "Texts in the user's
 * language"): parameters other than strings and numbers are left out. */
function parseSaid(value: Record<string, unknown>): {
  message_id?: string;
  params?: Record<string, string | number>;
} {
  if (typeof value.message_id !== "string") return {};
  const params: Record<string, string | number> = {};
  if (isRecord(value.params)) {
    for (const [name, param] of Object.entries(value.params)) {
      if (typeof param === "string" || typeof param === "number") params[name] = param;
    }
  }
  return { message_id: value.message_id, params };
}

function parseEvent(value: unknown): LiveEvent | null {
  if (!isRecord(value) || typeof value.message !== "string") return null;
  return {
    time: typeof value.time === "number" ? value.time : Date.now() / 1000,
    node: typeof value.node === "number" ? value.node : null,
    kind: (typeof value.kind === "string" ? value.kind : "bus") as LiveEventKind,
    message: value.message,
    ...parseSaid(value),
  };
}

/** A timeline event as GET /api/events lists it (the id orders it and shows gaps). */
function parseTimelineEvent(value: unknown): TimelineEvent | null {
  if (
    !isRecord(value) ||
    typeof value.id !== "number" ||
    typeof value.kind !== "string" ||
    typeof value.message !== "string"
  ) {
    return null;
  }
  return {
    id: value.id,
    time: typeof value.time === "number" ? value.time : Date.now() / 1000,
    kind: value.kind,
    node: typeof value.node === "number" ? value.node : null,
    message: value.message,
    data: isRecord(value.data) ? value.data : {},
    ...parseSaid(value),
  };
}

/** A node's active fault (null: none), as the banner shows it. */
function parseFault(data: Record<string, unknown>): ServerMessage | null {
  if (typeof data.node !== "number") return null;
  const fault = data.fault;
  if (fault === null) return { type: "fault", node: data.node, fault: null };
  if (!isRecord(fault) || typeof fault.code !== "number" || typeof fault.name_en !== "string") {
    return null;
  }
  return { type: "fault", node: data.node, fault: { ...fault, node: data.node } as Fault };
}

/** A drive state pushed for a watched node: under `state` or `drive`, or the message itself. */
function parseDriveState(data: Record<string, unknown>): DriveState | null {
  const candidates = [data.state, data.drive, data];
  for (const candidate of candidates) {
    if (
      isRecord(candidate) &&
      typeof candidate.node === "number" &&
      typeof candidate.statusword === "number" &&
      typeof candidate.state === "string"
    ) {
      return candidate as unknown as DriveState;
    }
  }
  return null;
}

/** Who holds a node's control: under `controller`, or the message itself. */
function parseController(data: Record<string, unknown>): ControllerInfo | null {
  const candidate = isRecord(data.controller) ? data.controller : data;
  if (typeof candidate.node !== "number" || !("holder" in candidate)) return null;
  const holder = candidate.holder;
  if (holder !== null && !isRecord(holder)) return null;
  return candidate as unknown as ControllerInfo;
}

/** Parse one text frame; null for anything that is not a known, well-formed message. */
export function parseMessage(text: string): ServerMessage | null {
  let data: unknown;
  try {
    data = JSON.parse(text);
  } catch {
    return null; // not JSON: ignore, the next bus/nodes message replaces it anyway
  }
  if (!isRecord(data)) return null;
  switch (data.type) {
    case "bus":
      return isRecord(data.bus) && typeof data.bus.state === "string"
        ? { type: "bus", bus: data.bus as unknown as BusStatus }
        : null;
    case "nodes": {
      if (!Array.isArray(data.nodes)) return null;
      const nodes = data.nodes.map(parseNode).filter((n): n is LiveNode => n !== null);
      return { type: "nodes", nodes };
    }
    case "event": {
      const event = parseEvent(data.event);
      return event ? { type: "event", event } : null;
    }
    case "history": {
      if (!Array.isArray(data.events)) return null;
      const events = data.events.map(parseEvent).filter((e): e is LiveEvent => e !== null);
      return { type: "history", events };
    }
    case "pong":
      return { type: "pong" };
    case "timeline": {
      const event = parseTimelineEvent(data.event);
      return event ? { type: "timeline", event } : null;
    }
    case "fault":
      return parseFault(data);
    case "drive_state": {
      const state = parseDriveState(data);
      return state ? { type: "drive_state", state } : null;
    }
    case "controller": {
      const controller = parseController(data);
      return controller ? { type: "controller", controller } : null;
    }
    case "jog_stopped":
      return isRecord(data.jog) && typeof data.jog.jog_id === "string"
        ? { type: "jog_stopped", jog: data.jog as unknown as JogInfo }
        : null;
    default:
      return null;
  }
}
