// The live store: bus status, node states and recent events from the WebSocket, plus the node
// list from REST. It lives outside React state; components read slices of it through
// useSyncExternalStore, so a 5 Hz node update re-renders only what shows node states.
import type { ControllerInfo, DriveState, JogInfo } from "../api/drive";
import type { Fault } from "../api/faults";
import type { TimelineEvent } from "../api/timeline";
import type { BusStatus, NodeInfo } from "../api/types";
import type { ClientMessage, LiveEvent, LiveNode, ServerMessage } from "./messages";

export const EVENT_LIMIT = 200;

export type LinkState = "connecting" | "open" | "closed";

export interface LinkStatus {
  state: LinkState;
  /** Failed attempts since the last successful connection. */
  attempt: number;
  /** Epoch ms of the next reconnect attempt while closed, else null. */
  retryAt: number | null;
}

export interface LiveSnapshot {
  link: LinkStatus;
  bus: BusStatus | null;
  /** Live state per node id; an entry keeps its identity while its fields do not change. */
  nodes: Readonly<Record<number, LiveNode>>;
  /** Sorted ids of the nodes the WebSocket reports; same array while the set is unchanged. */
  liveIds: readonly number[];
  /** Node details from GET /api/nodes (name, identity, profile). */
  infos: readonly NodeInfo[];
  /** Why the last GET /api/nodes failed, if it did. */
  infosError: string | null;
  /** Oldest first, at most EVENT_LIMIT. */
  events: readonly LiveEvent[];
  /** Drive states pushed for the nodes a page watches (watch_drive). */
  drives: Readonly<Record<number, DriveState>>;
  /** Epoch ms each node's drive state last arrived on the socket. */
  drivesAt: Readonly<Record<number, number>>;
  /** Who holds each node's motion control, as last pushed. */
  controllers: Readonly<Record<number, ControllerInfo>>;
  /** Epoch ms each node's controller message last arrived. */
  controllersAt: Readonly<Record<number, number>>;
  /** The last jog the server reported stopped (keep-alive missed, EMCY, page hidden …). */
  jogStopped: JogInfo | null;
  /** The active fault of each node in fault (`fault` messages, and GET /api/faults/active). */
  faults: Readonly<Record<number, Fault>>;
}

type Listener = () => void;
type TimelineListener = (event: TimelineEvent) => void;
/** A `fault` message: the node's active fault now (null: none). */
type FaultListener = (node: number, fault: Fault | null) => void;

/** Sends a message on the live socket; false when it is not open. */
export type Sender = (message: ClientMessage) => boolean;

const INITIAL: LiveSnapshot = {
  link: { state: "connecting", attempt: 0, retryAt: null },
  bus: null,
  nodes: {},
  liveIds: [],
  infos: [],
  infosError: null,
  events: [],
  drives: {},
  drivesAt: {},
  controllers: {},
  controllersAt: {},
  jogStopped: null,
  faults: {},
};

function sameNode(a: LiveNode, b: LiveNode): boolean {
  return (
    a.nmt_state === b.nmt_state &&
    a.online === b.online &&
    a.heartbeat_age_ms === b.heartbeat_age_ms
  );
}

function sameFault(a: Fault, b: Fault): boolean {
  return JSON.stringify(a) === JSON.stringify(b);
}

function sameIds(a: readonly number[], b: readonly number[]): boolean {
  return a.length === b.length && a.every((id, i) => id === b[i]);
}

export class LiveStore {
  private snapshot: LiveSnapshot = INITIAL;
  private readonly listeners = new Set<Listener>();
  private sender: Sender | null = null;
  private readonly timelineListeners = new Set<TimelineListener>();
  private readonly faultListeners = new Set<FaultListener>();
  /** Counts `fault` messages; faultTouched holds the count at each node's latest one. */
  private faultSeq = 0;
  private readonly faultTouched = new Map<number, number>();

  // Arrow functions: React calls these detached from the instance.
  subscribe = (listener: Listener): (() => void) => {
    this.listeners.add(listener);
    return () => this.listeners.delete(listener);
  };

  getSnapshot = (): LiveSnapshot => this.snapshot;

  apply(message: ServerMessage): void {
    switch (message.type) {
      case "bus":
        this.update({ bus: message.bus });
        return;
      case "nodes":
        this.applyNodes(message.nodes);
        return;
      case "event":
        this.update({ events: [...this.snapshot.events, message.event].slice(-EVENT_LIMIT) });
        return;
      case "history":
        // the server's recent events, sent first on every connection: replacing (not
        // appending) keeps a reconnect from listing them twice
        this.update({ events: message.events.slice(-EVENT_LIMIT) });
        return;
      case "pong":
        return;
      case "timeline":
        // a stream, not a state: each list keeps what matches its filter
        for (const listener of this.timelineListeners) listener(message.event);
        return;
      case "fault": {
        this.faultSeq += 1;
        this.faultTouched.set(message.node, this.faultSeq);
        const faults: Record<number, Fault> = {};
        for (const fault of Object.values(this.snapshot.faults)) {
          if (fault.node !== message.node) faults[fault.node] = fault;
        }
        if (message.fault) faults[message.node] = message.fault;
        this.update({ faults });
        for (const listener of this.faultListeners) listener(message.node, message.fault);
        return;
      }
      case "drive_state": {
        const { node } = message.state;
        this.update({
          drives: { ...this.snapshot.drives, [node]: message.state },
          drivesAt: { ...this.snapshot.drivesAt, [node]: Date.now() },
        });
        return;
      }
      case "controller":
        this.update({
          controllers: {
            ...this.snapshot.controllers,
            [message.controller.node]: message.controller,
          },
          controllersAt: { ...this.snapshot.controllersAt, [message.controller.node]: Date.now() },
        });
        return;
      case "jog_stopped":
        this.update({ jogStopped: message.jog });
        return;
    }
  }

  /** Called with every `timeline` event as it arrives; returns the unsubscribe. */
  subscribeTimeline(listener: TimelineListener): () => void {
    this.timelineListeners.add(listener);
    return () => this.timelineListeners.delete(listener);
  }

  /** Called with every `fault` message as it arrives, also one that changes nothing in
   * `faults`: the server sends one when a node's EMCYs are stored in its history (the Faults
   * page reads the history then). Returns the unsubscribe. */
  subscribeFaults(listener: FaultListener): () => void {
    this.faultListeners.add(listener);
    return () => this.faultListeners.delete(listener);
  }

  /** Where the `fault` messages are now: pass it to setActiveFaults with a REST answer. */
  faultVersion(): number {
    return this.faultSeq;
  }

  /** Replace the active faults with GET /api/faults/active's answer, requested at `version`:
   * a node whose `fault` message came after the request keeps what that message said. */
  setActiveFaults(faults: readonly Fault[], version: number): void {
    const current = this.snapshot.faults;
    const next: Record<number, Fault> = {};
    for (const fault of faults) {
      if ((this.faultTouched.get(fault.node) ?? 0) <= version) next[fault.node] = fault;
    }
    for (const [node, seq] of this.faultTouched) {
      const kept = current[node];
      if (seq > version && kept) next[node] = kept;
    }
    this.update({ faults: next });
  }

  /** One node's active fault from a REST answer requested at `version` (GET
   * /api/nodes/{node}/faults, a fault reset's answer): ignored when a `fault` message for the
   * node came after the request; the same fault keeps its object (nothing re-renders). */
  setNodeFault(node: number, fault: Fault | null, version: number): void {
    if ((this.faultTouched.get(node) ?? 0) > version) return;
    const current = this.snapshot.faults[node];
    if (fault === null ? current === undefined : current && sameFault(current, fault)) return;
    const faults: Record<number, Fault> = {};
    for (const kept of Object.values(this.snapshot.faults)) {
      if (kept.node !== node) faults[kept.node] = kept;
    }
    if (fault) faults[node] = fault;
    this.update({ faults });
  }

  /** The connection hands in how to reach the server (null while it has none). */
  setSender(sender: Sender | null): void {
    this.sender = sender;
  }

  /** Send on the live socket; false when there is none open (the caller falls back to REST). */
  send(message: ClientMessage): boolean {
    return this.sender?.(message) ?? false;
  }

  setLink(link: LinkStatus): void {
    const old = this.snapshot.link;
    if (old.state === link.state && old.attempt === link.attempt && old.retryAt === link.retryAt) {
      return;
    }
    this.update({ link });
  }

  setInfos(infos: readonly NodeInfo[]): void {
    this.update({ infos: [...infos].sort((a, b) => a.node - b.node), infosError: null });
  }

  setInfosError(message: string): void {
    this.update({ infosError: message });
  }

  /** Merge one node's details (after NMT, EDS import, node-id change) without a refetch. */
  upsertInfo(info: NodeInfo): void {
    const rest = this.snapshot.infos.filter((i) => i.node !== info.node);
    this.setInfos([...rest, info]);
  }

  private applyNodes(incoming: readonly LiveNode[]): void {
    const previous = this.snapshot.nodes;
    const nodes: Record<number, LiveNode> = {};
    let changed = Object.keys(previous).length !== incoming.length;
    for (const node of incoming) {
      const old = previous[node.node];
      if (old && sameNode(old, node)) {
        nodes[node.node] = old;
      } else {
        nodes[node.node] = node;
        changed = true;
      }
    }
    if (!changed) return;
    const ids = incoming.map((n) => n.node).sort((a, b) => a - b);
    const liveIds = sameIds(ids, this.snapshot.liveIds) ? this.snapshot.liveIds : ids;
    this.update({ nodes, liveIds });
  }

  private update(patch: Partial<LiveSnapshot>): void {
    this.snapshot = { ...this.snapshot, ...patch };
    for (const listener of this.listeners) listener();
  }
}
