import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";

import type { TimelineEvent } from "../api/timeline";
import { mdiAlarm4 } from "../test/fixtures/faults";
import { LiveConnection, type SocketLike } from "./connection";
import { parseMessage } from "./messages";
import { LiveStore } from "./store";

class FakeSocket implements SocketLike {
  sent: string[] = [];
  onopen: ((event: Event) => void) | null = null;
  onmessage: ((event: MessageEvent) => void) | null = null;
  onclose: ((event: CloseEvent) => void) | null = null;
  onerror: ((event: Event) => void) | null = null;
  send(data: string): void {
    this.sent.push(data);
  }
  close(): void {
    this.onclose = null;
  }
  receive(message: unknown): void {
    this.onmessage?.(new MessageEvent("message", { data: JSON.stringify(message) }));
  }
}

const ev = (id: number): TimelineEvent => ({
  id,
  time: 1_764_000_000 + id,
  kind: "emcy",
  node: 1,
  message: `event ${id}`,
  data: { code: 0x5ff0 },
});

beforeEach(() => {
  vi.useFakeTimers();
});

afterEach(() => {
  vi.useRealTimers();
});

describe("timeline and fault messages", () => {
  it("parses them and drops malformed ones", () => {
    expect(parseMessage(JSON.stringify({ type: "timeline", event: ev(3) }))).toEqual({
      type: "timeline",
      event: ev(3),
    });
    const fault = mdiAlarm4();
    expect(parseMessage(JSON.stringify({ type: "fault", node: 1, fault }))).toEqual({
      type: "fault",
      node: 1,
      fault,
    });
    expect(parseMessage(JSON.stringify({ type: "fault", node: 1, fault: null }))).toEqual({
      type: "fault",
      node: 1,
      fault: null,
    });
    expect(parseMessage(JSON.stringify({ type: "timeline", event: { id: "x" } }))).toBeNull();
    expect(parseMessage(JSON.stringify({ type: "fault", fault: null }))).toBeNull();
    expect(parseMessage(JSON.stringify({ type: "fault", node: 1, fault: { code: 1 } }))).toBeNull();
  });

  it("keeps active faults per node from the socket and streams timeline events", () => {
    const store = new LiveStore();
    const socket = new FakeSocket();
    const connection = new LiveConnection(store, {
      url: "ws://x/api/ws",
      createSocket: () => socket,
    });
    const seen: number[] = [];
    const unsubscribe = store.subscribeTimeline((e) => seen.push(e.id));
    connection.start();
    socket.onopen?.(new Event("open"));

    socket.receive({ type: "fault", node: 1, fault: mdiAlarm4() });
    socket.receive({ type: "fault", node: 2, fault: { ...mdiAlarm4(), node: 2 } });
    expect(Object.keys(store.getSnapshot().faults)).toEqual(["1", "2"]);
    socket.receive({ type: "fault", node: 1, fault: null });
    expect(Object.keys(store.getSnapshot().faults)).toEqual(["2"]);

    socket.receive({ type: "timeline", event: ev(4) });
    socket.receive({ type: "timeline", event: ev(5) });
    unsubscribe();
    socket.receive({ type: "timeline", event: ev(6) });
    expect(seen).toEqual([4, 5]);
    connection.stop();
  });

  it("lets a REST answer not undo a fault message that came after the request", () => {
    const store = new LiveStore();
    const version = store.faultVersion();
    // while GET /api/faults/active runs: node 1's fault is reset, node 3 faults
    store.apply({ type: "fault", node: 1, fault: null });
    store.apply({ type: "fault", node: 3, fault: { ...mdiAlarm4(), node: 3 } });
    store.setActiveFaults([mdiAlarm4(), { ...mdiAlarm4(), node: 2 }], version);
    expect(Object.keys(store.getSnapshot().faults)).toEqual(["2", "3"]);
    // a later read replaces everything
    store.setActiveFaults([], store.faultVersion());
    expect(store.getSnapshot().faults).toEqual({});
  });

  it("takes one node's fault from REST unless a fault message for it came after the request", () => {
    const store = new LiveStore();
    const version = store.faultVersion();
    store.apply({ type: "fault", node: 1, fault: null }); // reset while the request ran
    store.setNodeFault(1, mdiAlarm4(), version);
    store.setNodeFault(2, { ...mdiAlarm4(), node: 2 }, version); // no message for node 2
    expect(Object.keys(store.getSnapshot().faults)).toEqual(["2"]);

    // the same fault again keeps its object: nothing re-renders
    const before = store.getSnapshot();
    store.setNodeFault(2, { ...mdiAlarm4(), node: 2 }, store.faultVersion());
    expect(store.getSnapshot()).toBe(before);
    store.setNodeFault(2, null, store.faultVersion());
    expect(store.getSnapshot().faults).toEqual({});
  });

  it("tells fault listeners of every fault message, also one that changes nothing", () => {
    const store = new LiveStore();
    const seen: [number, number | null][] = [];
    const unsubscribe = store.subscribeFaults((node, fault) =>
      seen.push([node, fault?.code ?? null]),
    );
    store.apply({ type: "fault", node: 1, fault: mdiAlarm4() });
    store.apply({ type: "fault", node: 1, fault: null });
    store.apply({ type: "fault", node: 1, fault: null }); // the history changed: sent again
    unsubscribe();
    store.apply({ type: "fault", node: 2, fault: null });
    expect(seen).toEqual([
      [1, 4],
      [1, null],
      [1, null],
    ]);
  });
});
