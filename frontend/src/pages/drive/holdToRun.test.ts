import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";

import { HoldToRun, type HoldTransport } from "./holdToRun";

beforeEach(() => {
  vi.useFakeTimers();
});

afterEach(() => {
  vi.useRealTimers();
});

/** A transport whose start answers when the test says so. */
function transport(): HoldTransport & {
  log: string[];
  answer: (id: string) => Promise<void>;
  refuse: (message: string) => Promise<void>;
  failKeepalive: boolean;
} {
  let resolve: (id: string) => void = () => undefined;
  let reject: (error: Error) => void = () => undefined;
  const t = {
    log: [] as string[],
    failKeepalive: false,
    start: () => {
      t.log.push("start");
      return new Promise<string>((res, rej) => {
        resolve = res;
        reject = rej;
      });
    },
    keepalive: (id: string) => {
      t.log.push(`keepalive ${id}`);
      return t.failKeepalive ? Promise.reject(new Error("jog expired")) : Promise.resolve();
    },
    stop: (id: string) => {
      t.log.push(`stop ${id}`);
    },
    answer: async (id: string) => {
      resolve(id);
      await Promise.resolve();
      await Promise.resolve();
    },
    refuse: async (message: string) => {
      reject(new Error(message));
      await Promise.resolve();
      await Promise.resolve();
    },
  };
  return t;
}

describe("HoldToRun", () => {
  it("sends a keep-alive every 100 ms while held and stops on release", async () => {
    const t = transport();
    const hold = new HoldToRun(t);
    hold.press();
    expect(hold.state.phase).toBe("starting");
    await t.answer("j1");
    expect(hold.state).toEqual({ phase: "running", jogId: "j1", error: null });
    vi.advanceTimersByTime(350);
    expect(t.log).toEqual(["start", "keepalive j1", "keepalive j1", "keepalive j1"]);
    hold.release();
    expect(hold.state.phase).toBe("idle");
    vi.advanceTimersByTime(1000);
    expect(t.log.slice(4)).toEqual(["stop j1"]);
  });

  it("stops a jog whose start is answered after the release", async () => {
    const t = transport();
    const hold = new HoldToRun(t);
    hold.press();
    hold.release();
    await t.answer("late");
    vi.advanceTimersByTime(500);
    expect(t.log).toEqual(["start", "stop late"]);
    expect(hold.state.phase).toBe("idle");
  });

  it("ignores a second press while held", async () => {
    const t = transport();
    const hold = new HoldToRun(t);
    hold.press();
    hold.press();
    await t.answer("j1");
    expect(t.log).toEqual(["start"]);
  });

  it("reports a refused start", async () => {
    const t = transport();
    const changes: string[] = [];
    const hold = new HoldToRun(t, { onChange: (s) => changes.push(s.phase) });
    hold.press();
    await t.refuse("Drive not enabled");
    expect(hold.state).toEqual({ phase: "idle", jogId: null, error: "Drive not enabled" });
    expect(changes).toEqual(["starting", "idle"]);
  });

  it("ends the hold when the server no longer knows the jog", async () => {
    const t = transport();
    const hold = new HoldToRun(t);
    hold.press();
    await t.answer("j1");
    t.failKeepalive = true;
    vi.advanceTimersByTime(100);
    await Promise.resolve();
    await Promise.resolve();
    expect(hold.state).toEqual({ phase: "idle", jogId: null, error: "jog expired" });
    vi.advanceTimersByTime(500);
    expect(t.log.filter((l) => l.startsWith("keepalive"))).toHaveLength(1);
  });

  it("can be held again after a release", async () => {
    const t = transport();
    const hold = new HoldToRun(t);
    hold.press();
    await t.answer("j1");
    hold.release();
    hold.press();
    await t.answer("j2");
    vi.advanceTimersByTime(100);
    expect(t.log).toEqual(["start", "stop j1", "start", "keepalive j2"]);
    hold.release();
  });
});
