import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";

import { backoffDelay } from "./backoff";
import { LiveConnection, liveUrl, type SocketLike } from "./connection";
import { LiveStore } from "./store";

/** A WebSocket stand-in the test opens, feeds and closes by hand. */
class FakeSocket implements SocketLike {
  sent: string[] = [];
  closed = false;
  onopen: ((event: Event) => void) | null = null;
  onmessage: ((event: MessageEvent) => void) | null = null;
  onclose: ((event: CloseEvent) => void) | null = null;
  onerror: ((event: Event) => void) | null = null;
  constructor(readonly url: string) {}
  send(data: string): void {
    this.sent.push(data);
  }
  close(): void {
    this.closed = true;
  }
  open(): void {
    this.onopen?.(new Event("open"));
  }
  receive(data: unknown): void {
    this.onmessage?.(new MessageEvent("message", { data: JSON.stringify(data) }));
  }
  drop(code?: number): void {
    this.onclose?.(new CloseEvent("close", code === undefined ? {} : { code }));
  }
}

function setup(onRefused?: () => void) {
  const sockets: FakeSocket[] = [];
  const store = new LiveStore();
  const connection = new LiveConnection(store, {
    url: "ws://test/api/ws",
    ...(onRefused ? { onRefused } : {}),
    createSocket: (url) => {
      const socket = new FakeSocket(url);
      sockets.push(socket);
      return socket;
    },
    random: () => 0, // no jitter: exact delays
  });
  const last = (): FakeSocket => {
    const socket = sockets.at(-1);
    if (!socket) throw new Error("no socket opened");
    return socket;
  };
  return { sockets, store, connection, last };
}

beforeEach(() => {
  vi.useFakeTimers();
});

afterEach(() => {
  vi.useRealTimers();
});

describe("backoffDelay", () => {
  it("doubles from 500 ms up to 10 s, plus jitter", () => {
    const delays = [0, 1, 2, 3, 4, 5, 6].map((n) => backoffDelay(n, undefined, () => 0));
    expect(delays).toEqual([500, 1000, 2000, 4000, 8000, 10000, 10000]);
    expect(backoffDelay(0, undefined, () => 1)).toBe(600);
  });
});

describe("LiveConnection", () => {
  it("builds the socket URL from the page origin", () => {
    expect(liveUrl({ protocol: "http:", host: "127.0.0.1:8000" })).toBe(
      "ws://127.0.0.1:8000/api/ws",
    );
    expect(liveUrl({ protocol: "https:", host: "desk.local" })).toBe("wss://desk.local/api/ws");
  });

  it("reports a close for want of a login (1008) and keeps retrying", () => {
    const refused = vi.fn();
    const { sockets, connection, last } = setup(refused);
    connection.start();
    last().drop();
    expect(refused).not.toHaveBeenCalled();
    vi.advanceTimersByTime(500);
    last().drop(1008);
    expect(refused).toHaveBeenCalledTimes(1);
    vi.advanceTimersByTime(1000);
    expect(sockets).toHaveLength(3);
    connection.stop();
  });

  it("shows the link state and feeds messages into the store", () => {
    const { store, connection, last } = setup();
    connection.start();
    expect(store.getSnapshot().link.state).toBe("connecting");
    last().open();
    expect(store.getSnapshot().link.state).toBe("open");
    last().receive({
      type: "nodes",
      nodes: [{ node: 3, nmt_state: "operational", online: true, heartbeat_age_ms: 8 }],
    });
    expect(store.getSnapshot().nodes[3]?.nmt_state).toBe("operational");
    connection.stop();
  });

  it("reconnects with growing delays while the server is away", () => {
    const { sockets, store, connection, last } = setup();
    connection.start();
    last().drop(); // first attempt fails
    expect(store.getSnapshot().link).toMatchObject({ state: "closed", attempt: 1 });
    vi.advanceTimersByTime(499);
    expect(sockets).toHaveLength(1);
    vi.advanceTimersByTime(1);
    expect(sockets).toHaveLength(2);
    last().drop();
    vi.advanceTimersByTime(999);
    expect(sockets).toHaveLength(2);
    vi.advanceTimersByTime(1);
    expect(sockets).toHaveLength(3);
    last().drop();
    vi.advanceTimersByTime(2000);
    expect(sockets).toHaveLength(4);
    connection.stop();
  });

  it("starts again from the shortest delay after a successful connection", () => {
    const { sockets, connection, last } = setup();
    connection.start();
    last().drop();
    vi.advanceTimersByTime(500);
    last().drop();
    vi.advanceTimersByTime(1000);
    last().open(); // third try works
    last().drop(); // and is lost later
    vi.advanceTimersByTime(500);
    expect(sockets).toHaveLength(4);
    connection.stop();
  });

  it("pings every 10 s while open", () => {
    const { connection, last } = setup();
    connection.start();
    last().open();
    vi.advanceTimersByTime(5000);
    last().receive({ type: "pong" });
    vi.advanceTimersByTime(5000);
    expect(last().sent).toEqual(['{"type":"ping"}']);
    last().receive({ type: "pong" });
    vi.advanceTimersByTime(10000);
    expect(last().sent).toHaveLength(2);
    connection.stop();
  });

  it("gives up on a silent link and reconnects", () => {
    const { sockets, store, connection, last } = setup();
    connection.start();
    last().open();
    const silent = last();
    vi.advanceTimersByTime(30000); // no message at all: the 30 s tick finds it stale
    expect(silent.closed).toBe(true);
    expect(store.getSnapshot().link.state).toBe("closed");
    vi.advanceTimersByTime(500);
    expect(sockets).toHaveLength(2);
    connection.stop();
  });

  it("stops for good on stop()", () => {
    const { sockets, store, connection, last } = setup();
    connection.start();
    last().open();
    connection.stop();
    expect(last().closed).toBe(true);
    vi.advanceTimersByTime(60000);
    expect(sockets).toHaveLength(1);
    expect(store.getSnapshot().link).toMatchObject({ state: "closed", retryAt: null });
  });
});
