import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";

import { DRIVE } from "../test/fixtures/drive";
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
}

beforeEach(() => {
  vi.useFakeTimers();
});

afterEach(() => {
  vi.useRealTimers();
});

describe("drive messages", () => {
  it.each([
    ["under state", { type: "drive_state", state: DRIVE }],
    ["under drive", { type: "drive_state", drive: DRIVE }],
    ["flat", { ...DRIVE, type: "drive_state", state: DRIVE.state }],
  ])("reads a drive state %s", (_, message) => {
    const parsed = parseMessage(JSON.stringify(message));
    expect(parsed?.type).toBe("drive_state");
    if (parsed?.type === "drive_state") expect(parsed.state.statusword).toBe(DRIVE.statusword);
  });

  it("reads who holds control, and drops a malformed one", () => {
    const controller = {
      node: 1,
      holder: { client_id: "abc", name: "Chrome tab abc", since: 1 },
      you: false,
    };
    expect(parseMessage(JSON.stringify({ type: "controller", ...controller }))).toEqual({
      type: "controller",
      controller: { type: "controller", ...controller },
    });
    expect(parseMessage('{"type":"controller","node":1,"holder":7}')).toBeNull();
    expect(parseMessage('{"type":"drive_state","state":{"node":1}}')).toBeNull();
  });

  it("keeps the last state per node with its arrival time", () => {
    const store = new LiveStore();
    vi.setSystemTime(5000);
    store.apply({ type: "drive_state", state: DRIVE });
    expect(store.getSnapshot().drives[1]).toBe(DRIVE);
    expect(store.getSnapshot().drivesAt[1]).toBe(5000);
  });
});

describe("LiveConnection hello and send", () => {
  it("says hello first on every connection and sends only while open", () => {
    const store = new LiveStore();
    const sockets: FakeSocket[] = [];
    const connection = new LiveConnection(store, {
      url: "ws://test/api/ws",
      createSocket: () => {
        const socket = new FakeSocket();
        sockets.push(socket);
        return socket;
      },
      hello: { type: "hello", client_id: "tab-1", name: "Chrome tab" },
    });
    connection.start();
    const socket = sockets[0] as FakeSocket;
    expect(connection.send({ type: "watch_drive", node: 1 })).toBe(false);
    socket.onopen?.(new Event("open"));
    expect(connection.send({ type: "jog_keepalive", jog_id: "j1" })).toBe(true);
    expect(socket.sent.map((s) => JSON.parse(s) as unknown)).toEqual([
      { type: "hello", client_id: "tab-1", name: "Chrome tab" },
      { type: "jog_keepalive", jog_id: "j1" },
    ]);
    connection.stop();
  });

  it("reaches the socket through the store's sender", () => {
    const store = new LiveStore();
    expect(store.send({ type: "page_hidden" })).toBe(false);
    const sent: unknown[] = [];
    store.setSender((message) => sent.push(message) > 0);
    expect(store.send({ type: "page_hidden" })).toBe(true);
    expect(sent).toEqual([{ type: "page_hidden" }]);
  });
});
