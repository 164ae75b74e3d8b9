// Messages on the live WebSocket /api/ws (docs/api.md, "WebSocket"). They are not part of the
// OpenAPI schema, so they are described here and checked on arrival: a malformed message is
// dropped instead of corrupting the store.
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
}

export type ServerMessage =
  | { type: "bus"; bus: BusStatus }
  | { type: "nodes"; nodes: LiveNode[] }
  | { type: "event"; event: LiveEvent }
  | { type: "history"; events: LiveEvent[] }
  | { type: "pong" };

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

function parseEvent(value: unknown): LiveEvent | null {
  if (!isRecord(value) || typeof value.message !== "string") return null;
  return {
    time: typeof value.time === "number" ? value.time : Date.now() / 1000,
    node: typeof value.node === "number" ? value.node : null,
    kind: (typeof value.kind === "string" ? value.kind : "bus") as LiveEventKind,
    message: value.message,
  };
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
    default:
      return null;
  }
}
