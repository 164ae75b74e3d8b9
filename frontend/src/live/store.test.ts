import { describe, expect, it, vi } from "vitest";

import type { BusStatus, NodeInfo } from "../api/types";
import { parseMessage, type LiveNode } from "./messages";
import { EVENT_LIMIT, LiveStore } from "./store";

const bus: BusStatus = {
  state: "connected",
  interface: "virtual",
  channel: "sim",
  bitrate: 500000,
  simulated: true,
  error: null,
  rx_frames: 10,
  tx_frames: 4,
  error_frames: 0,
  bus_errors: 0,
  reconnects: 0,
  since: 1,
};

const node = (
  id: number,
  state: LiveNode["nmt_state"] = "operational",
  age: number | null = 50,
): LiveNode => ({
  node: id,
  nmt_state: state,
  online: true,
  heartbeat_age_ms: age,
});

describe("LiveStore", () => {
  it("replaces the snapshot and notifies subscribers on a bus message", () => {
    const store = new LiveStore();
    const listener = vi.fn();
    store.subscribe(listener);
    const before = store.getSnapshot();
    store.apply({ type: "bus", bus });
    expect(listener).toHaveBeenCalledTimes(1);
    expect(store.getSnapshot()).not.toBe(before);
    expect(store.getSnapshot().bus?.rx_frames).toBe(10);
  });

  it("keeps an unchanged node's object so its subscribers skip re-rendering", () => {
    const store = new LiveStore();
    store.apply({ type: "nodes", nodes: [node(1), node(2)] });
    const first = store.getSnapshot();
    store.apply({ type: "nodes", nodes: [node(1), node(2, "stopped")] });
    const second = store.getSnapshot();
    expect(second.nodes[1]).toBe(first.nodes[1]);
    expect(second.nodes[2]?.nmt_state).toBe("stopped");
    expect(second.liveIds).toBe(first.liveIds); // same set of ids: same array
  });

  it("does not notify when a nodes message changes nothing", () => {
    const store = new LiveStore();
    store.apply({ type: "nodes", nodes: [node(1)] });
    const listener = vi.fn();
    store.subscribe(listener);
    store.apply({ type: "nodes", nodes: [node(1)] });
    expect(listener).not.toHaveBeenCalled();
  });

  it("reports a new id set when a node appears or leaves", () => {
    const store = new LiveStore();
    store.apply({ type: "nodes", nodes: [node(2), node(1)] });
    expect(store.getSnapshot().liveIds).toEqual([1, 2]);
    store.apply({ type: "nodes", nodes: [node(1)] });
    expect(store.getSnapshot().liveIds).toEqual([1]);
    expect(store.getSnapshot().nodes[2]).toBeUndefined();
  });

  it("keeps only the last events", () => {
    const store = new LiveStore();
    for (let i = 0; i < EVENT_LIMIT + 5; i += 1) {
      store.apply({
        type: "event",
        event: { time: i, node: 1, kind: "nmt", message: `event ${i}` },
      });
    }
    const { events } = store.getSnapshot();
    expect(events).toHaveLength(EVENT_LIMIT);
    expect(events[0]?.message).toBe("event 5");
    expect(events.at(-1)?.message).toBe(`event ${EVENT_LIMIT + 4}`);
  });

  it("replaces its events with the server's history, so a reconnect lists none twice", () => {
    const store = new LiveStore();
    const booted = { time: 1, node: 1, kind: "boot-up" as const, message: "node 1 booted" };
    const lost = { time: 2, node: 2, kind: "node-lost" as const, message: "node 2 lost" };
    store.apply({ type: "history", events: [booted] });
    store.apply({ type: "event", event: lost });
    store.apply({ type: "history", events: [booted, lost] });
    expect(store.getSnapshot().events).toEqual([booted, lost]);
  });

  it("stops notifying after unsubscribe", () => {
    const store = new LiveStore();
    const listener = vi.fn();
    const unsubscribe = store.subscribe(listener);
    unsubscribe();
    store.apply({ type: "bus", bus });
    expect(listener).not.toHaveBeenCalled();
  });

  it("sorts node details and merges one node's update", () => {
    const store = new LiveStore();
    const info = (id: number, name: string): NodeInfo => ({
      node: id,
      name,
      profile: "cia402",
      profile_label: "CiA 402",
      nmt_state: "unknown",
      online: true,
      od_source: "profile",
      od_filename: "cia402/drive.eds",
      od_warnings: 0,
    });
    store.setInfos([info(3, "c"), info(1, "a")]);
    store.upsertInfo(info(3, "renamed"));
    expect(store.getSnapshot().infos.map((i) => `${i.node}:${i.name ?? ""}`)).toEqual([
      "1:a",
      "3:renamed",
    ]);
  });
});

describe("parseMessage", () => {
  it("reads the three server messages and pong", () => {
    expect(parseMessage(JSON.stringify({ type: "bus", bus }))).toEqual({ type: "bus", bus });
    expect(parseMessage('{"type":"pong"}')).toEqual({ type: "pong" });
    expect(
      parseMessage(
        '{"type":"nodes","nodes":[{"node":1,"nmt_state":"stopped","online":true,"heartbeat_age_ms":12}]}',
      ),
    ).toEqual({ type: "nodes", nodes: [node(1, "stopped", 12)] });
    expect(
      parseMessage(
        '{"type":"event","event":{"time":5,"node":null,"kind":"bus","message":"bus error"}}',
      ),
    ).toEqual({ type: "event", event: { time: 5, node: null, kind: "bus", message: "bus error" } });
  });

  it("reads the history sent first on every connection", () => {
    expect(
      parseMessage(
        '{"type":"history","events":[{"time":5,"node":3,"kind":"nmt","message":"NMT stop"},7]}',
      ),
    ).toEqual({
      type: "history",
      events: [{ time: 5, node: 3, kind: "nmt", message: "NMT stop" }],
    });
  });

  it("drops what it cannot use", () => {
    expect(parseMessage("not json")).toBeNull();
    expect(parseMessage('{"type":"bus"}')).toBeNull();
    expect(parseMessage('{"type":"mystery"}')).toBeNull();
    expect(parseMessage("[1,2]")).toBeNull();
  });

  it("maps an unknown NMT state to unknown", () => {
    const message = parseMessage('{"type":"nodes","nodes":[{"node":4,"nmt_state":"sleeping"}]}');
    expect(message).toEqual({
      type: "nodes",
      nodes: [{ node: 4, nmt_state: "unknown", online: false, heartbeat_age_ms: null }],
    });
  });
});
