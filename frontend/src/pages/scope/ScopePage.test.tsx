import { cleanup, screen, waitFor, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { LiveStore } from "../../live/store";
import { json, stubFetch, type Handler } from "../../test/fetchStub";
import { renderPage } from "../../test/render";
import { INFO, PLAN, TREE, VIEWER, capture } from "./fixtures";
import { ScopePage } from "./ScopePage";
import type { Capture } from "./types";

afterEach(() => {
  vi.unstubAllGlobals();
  window.sessionStorage.clear();
});

const BASE = {
  "GET /api/scope/viewer": VIEWER,
  "GET /api/scope/captures": [],
  "GET /api/nodes/1/od": TREE,
  "POST /api/scope/plan": PLAN,
};

function render(routes: Record<string, Handler | object> = {}): ReturnType<typeof stubFetch> {
  const fetch = stubFetch({ ...BASE, ...routes });
  const store = new LiveStore();
  store.upsertInfo(INFO);
  renderPage(<ScopePage />, "/scope", store);
  return fetch;
}

async function pickPositionAndVelocity(): Promise<void> {
  await userEvent.click(await screen.findByRole("button", { name: "Position 6064h" }));
  await userEvent.click(screen.getByRole("button", { name: "Velocity 606Ch" }));
}

const STOPPED = capture({ state: "done", ended: 1_790_000_003, notes: ["stopped by the user"] });

/** The page with capture 7 recording; its polls and its stop answered by `poll` and `stop`. */
async function recording(poll: Handler, stop: Handler): Promise<void> {
  render({
    "POST /api/scope/captures": capture(),
    "GET /api/scope/captures/7": poll,
    "DELETE /api/scope/captures/7": stop,
  });
  await pickPositionAndVelocity();
  const start = screen.getByRole("button", { name: "● Start capture" });
  await waitFor(() => expect(start).toHaveProperty("disabled", false));
  await userEvent.click(start);
  expect((await screen.findByTestId("capture-state")).textContent).toBe("Recording");
}

/** Polls of capture 7 (still recording) that, while held, answer only when released. */
function heldPolls(): {
  poll: Handler;
  hold: (held: boolean) => void;
  release: () => void;
  waiting: () => number;
} {
  let held = false;
  let waiting = 0;
  let release: () => void = () => undefined;
  return {
    poll: async () => {
      if (held) {
        waiting += 1;
        await new Promise<void>((resolve) => (release = resolve));
      }
      return capture();
    },
    hold: (value) => (held = value),
    release: () => release(),
    waiting: () => waiting,
  };
}

describe("ScopePage", () => {
  it("checks the selection, starts a capture, follows it and stops it", async () => {
    let polled = 0;
    const running = capture();
    const fetch = render({
      "POST /api/scope/captures": running,
      "GET /api/scope/captures/7": () => {
        polled += 1;
        const progress: Capture = capture({ samples: 4500 + polled * 750 });
        progress.signals = progress.signals.map((s) => ({ ...s, last_value: polled }));
        return progress;
      },
      "DELETE /api/scope/captures/7": capture({
        state: "done",
        ended: 1_790_000_003,
        notes: ["stopped by the user"],
      }),
    });
    await pickPositionAndVelocity();
    const chosen = screen.getByRole("list", { name: "Chosen signals" });
    expect(within(chosen).getAllByRole("listitem")).toHaveLength(2);

    // the check runs by itself once the selection settles
    const sources = await screen.findByRole("table", { name: "Signal sources" });
    expect(within(sources).getByRole("row", { name: /6064h:00/ }).textContent).toContain("TPDO2");
    // on a busy machine the check may run between the two picks too: the last one has both
    const lastPlan = (): unknown =>
      JSON.parse(fetch.calls.filter((c) => c.path === "/api/scope/plan").at(-1)?.body ?? "{}");
    await waitFor(() => expect(lastPlan()).toHaveProperty("signals.length", 2));
    expect(lastPlan()).toMatchObject({
      signals: [
        { node: 1, index: 0x6064, subindex: 0 },
        { node: 1, index: 0x606c, subindex: 0 },
      ],
      sync_period_us: 1000,
      duration_s: 5,
      trigger: { kind: "none" },
    });
    const start = screen.getByRole("button", { name: "● Start capture" });
    await waitFor(() => expect(start).toHaveProperty("disabled", false));

    await userEvent.click(start);
    expect((await screen.findByTestId("capture-state")).textContent).toBe("Recording");
    const readouts = screen.getByRole("table", { name: "Live readouts" });
    expect(within(readouts).getByRole("row", { name: /606Ch:00/ }).textContent).toContain(
      "120 rpm",
    );
    expect(start).toHaveProperty("disabled", true);
    expect(screen.getByText(/Capture 7 is running: stop it before starting another/)).toBeTruthy();

    // ~4 polls a second: the samples and readouts move, the sparkline fills
    await waitFor(() => expect(polled).toBeGreaterThanOrEqual(2), { timeout: 2000 });
    await waitFor(() =>
      expect(screen.getByTestId("capture-samples").textContent).not.toBe("4,500"),
    );
    expect(
      screen.getByRole("img", { name: /Velocity actual value: last [2-9]\d* readings/ }),
    ).toBeTruthy();

    await userEvent.click(screen.getByRole("button", { name: "■ Stop" }));
    // the stop's answer: done, with the reason among the notes
    await waitFor(() => {
      expect(screen.getByTestId("capture-state").textContent).toBe("Done");
      expect(screen.getByText("stopped by the user")).toBeTruthy();
    });
    expect(fetch.calls.some((c) => c.method === "DELETE")).toBe(true);
  });

  it("keeps 'Done' when a poll sent before the stop answers after it", async () => {
    const polls = heldPolls();
    await recording(polls.poll, () => {
      polls.hold(false);
      return STOPPED;
    });
    polls.hold(true); // the next poll hangs until after the stop has answered
    await waitFor(() => expect(polls.waiting()).toBe(1));
    await userEvent.click(screen.getByRole("button", { name: "■ Stop" }));
    await waitFor(() => expect(screen.getByTestId("capture-state").textContent).toBe("Done"));
    polls.release();
    await new Promise((resolve) => setTimeout(resolve, 50));
    expect(screen.getByTestId("capture-state").textContent).toBe("Done");
  });

  it("keeps 'Done' when a poll sent while the stop was on its way answers after it", async () => {
    const polls = heldPolls();
    let releaseStop: () => void = () => undefined;
    await recording(polls.poll, async () => {
      polls.hold(true); // sent after the stop, answered after the stop's answer
      await new Promise<void>((resolve) => (releaseStop = resolve));
      return STOPPED;
    });
    await userEvent.click(screen.getByRole("button", { name: "■ Stop" }));
    await waitFor(() => expect(polls.waiting()).toBe(1)); // a poll left while stopping
    releaseStop();
    await waitFor(() => expect(screen.getByTestId("capture-state").textContent).toBe("Done"));
    polls.release();
    await new Promise((resolve) => setTimeout(resolve, 50));
    expect(screen.getByTestId("capture-state").textContent).toBe("Done");
  });

  it("says why a start is refused and keeps the selection", async () => {
    render({
      "POST /api/scope/captures": json(
        {
          error: "scope_busy",
          message: "capture 3 is still armed or running: stop it before starting another",
        },
        409,
      ),
    });
    await pickPositionAndVelocity();
    const start = screen.getByRole("button", { name: "● Start capture" });
    await waitFor(() => expect(start).toHaveProperty("disabled", false));
    await userEvent.click(start);
    expect((await screen.findByRole("alert")).textContent).toBe(
      "capture 3 is still armed or running: stop it before starting another",
    );
    const chosen = screen.getByRole("list", { name: "Chosen signals" });
    expect(within(chosen).getAllByRole("listitem")).toHaveLength(2);
  });

  it("blocks Start with the plan's problem", async () => {
    render({
      "POST /api/scope/plan": {
        ...PLAN,
        ok: false,
        problems: ["the capture would load the bus to 107 % at a 500 µs SYNC period"],
      },
    });
    await pickPositionAndVelocity();
    await screen.findByRole("list", { name: "Problems" });
    const start = screen.getByRole("button", { name: "● Start capture" });
    expect(start).toHaveProperty("disabled", true);
    const reason = document.getElementById(start.getAttribute("aria-describedby") ?? "");
    expect(reason?.textContent).toMatch(/107 %/);
  });

  it("lists the captures with exports, opens one from its .rrd and deletes one", async () => {
    let kept: Capture[] = [
      capture({ id: 5, name: "second", state: "done", size_bytes: 732296 }),
      capture({ id: 4, name: null, state: "failed", error: "RuntimeError: bus gone" }),
    ];
    const fetch = render({
      "GET /api/scope/captures": () => kept,
      "GET /api/scope/captures/5/export": () =>
        new Response(new Uint8Array([0x52, 0x52, 0x46, 0x32]), {
          headers: { "Content-Type": "application/octet-stream" },
        }),
      "DELETE /api/scope/captures/4": () => {
        kept = kept.filter((c) => c.id !== 4);
        return new Response(null, { status: 204 });
      },
    });
    const table = await screen.findByRole("table", { name: "Captures" });
    const rows = within(table).getAllByRole("row").slice(1);
    expect(rows.map((r) => r.getAttribute("data-capture"))).toEqual(["5", "4"]);
    expect(rows[0]?.textContent).toContain("715 KiB");
    expect(rows[1]?.textContent).toContain("RuntimeError: bus gone");
    const csv = within(table).getByRole("link", { name: "Export capture 5 as CSV" });
    expect(csv.getAttribute("href")).toBe("/api/scope/captures/5/export?format=csv");
    expect(csv.hasAttribute("download")).toBe(true);
    expect(
      within(table).getByRole("link", { name: "Export capture 5 as MF4" }).getAttribute("href"),
    ).toBe("/api/scope/captures/5/export?format=mf4");

    // the live viewer first; a finished capture goes to a viewer of its own, by its bytes
    const live = screen.getByTitle("rerun viewer");
    expect(live.getAttribute("src")).toBe(VIEWER.url);
    await userEvent.click(within(table).getByRole("button", { name: /Open capture 5/ }));
    const frame = screen.getByTitle<HTMLIFrameElement>("rerun viewer");
    expect(frame.getAttribute("src")).toBe("/rerun/");
    const handle = { open_channel: vi.fn(), send_rrd_to_channel: vi.fn(), close_channel: vi.fn() };
    Object.assign(frame.contentWindow ?? {}, { _handle: handle });
    await waitFor(() => expect(handle.send_rrd_to_channel).toHaveBeenCalled());
    expect(handle.open_channel).toHaveBeenCalledWith(
      "servodesk-capture-5",
      "ServoDesk capture 5 · second",
    );
    expect(fetch.urls.some((u) => u.endsWith("/api/scope/captures/5/export?format=rrd"))).toBe(
      true,
    );
    await userEvent.click(screen.getByRole("button", { name: "Back to the live view" }));
    expect(screen.getByTitle("rerun viewer").getAttribute("src")).toBe(VIEWER.url);

    await userEvent.click(within(table).getByRole("button", { name: "Delete capture 4" }));
    const dialog = screen.getByRole("dialog", { name: "Delete capture 4?" });
    await userEvent.click(within(dialog).getByRole("button", { name: "Delete capture 4" }));
    await waitFor(() =>
      expect(
        within(screen.getByRole("table", { name: "Captures" })).getAllByRole("row"),
      ).toHaveLength(2),
    );
    expect(screen.queryByRole("dialog")).toBeNull();
  });
});

describe("the live view switch", () => {
  afterEach(() => window.localStorage.clear());

  it("pauses the live viewer, remembers it over a remount and shows it again", async () => {
    render();
    expect((await screen.findByTestId("rerun-viewer")).getAttribute("src")).toBe(VIEWER.url);
    await userEvent.click(screen.getByRole("button", { name: "Pause live view" }));
    expect(screen.queryByTestId("rerun-viewer")).toBeNull();
    expect(screen.getByTestId("live-view-paused").textContent).toBe(
      "Live view paused: captures still record; open one from the list once it is done.",
    );
    expect(screen.getByText("Live view paused")).toBeTruthy();

    // the next visit (a remount) keeps it paused: no frame, no stream
    cleanup();
    render();
    expect(screen.getByRole("button", { name: "Show live view" })).toBeTruthy();
    expect(await screen.findByText(/rerun's own viewer/)).toBeTruthy(); // the viewer's answer came
    expect(screen.queryByTestId("rerun-viewer")).toBeNull();
    expect(screen.getByTestId("live-view-paused")).toBeTruthy();

    await userEvent.click(screen.getByRole("button", { name: "Show live view" }));
    expect(screen.getByTestId("rerun-viewer").getAttribute("src")).toBe(VIEWER.url);
    expect(screen.queryByTestId("live-view-paused")).toBeNull();
    expect(screen.getByText("Live: every capture as it records")).toBeTruthy();
    cleanup();
    render();
    expect((await screen.findByTestId("rerun-viewer")).getAttribute("src")).toBe(VIEWER.url);
  });

  it("opens a finished capture while paused and goes back to the paused panel", async () => {
    window.localStorage.setItem("servodesk.scope.liveView", "paused");
    render({
      "GET /api/scope/captures": [capture({ id: 5, name: "second", state: "done" })],
      "GET /api/scope/captures/5/export": () =>
        new Response(new Uint8Array([0x52, 0x52, 0x46, 0x32]), {
          headers: { "Content-Type": "application/octet-stream" },
        }),
    });
    expect(screen.queryByTestId("rerun-viewer")).toBeNull();
    const table = await screen.findByRole("table", { name: "Captures" });
    await userEvent.click(within(table).getByRole("button", { name: /Open capture 5/ }));
    const frame = screen.getByTestId<HTMLIFrameElement>("rerun-viewer");
    expect(frame.getAttribute("src")).toBe("/rerun/");
    expect(screen.queryByTestId("live-view-paused")).toBeNull();
    const handle = { open_channel: vi.fn(), send_rrd_to_channel: vi.fn(), close_channel: vi.fn() };
    Object.assign(frame.contentWindow ?? {}, { _handle: handle });
    await waitFor(() => expect(handle.send_rrd_to_channel).toHaveBeenCalled());

    await userEvent.click(screen.getByRole("button", { name: "Close the capture" }));
    expect(screen.queryByTestId("rerun-viewer")).toBeNull();
    expect(screen.getByTestId("live-view-paused")).toBeTruthy();
    expect(screen.getByRole("button", { name: "Show live view" })).toBeTruthy();
  });
});
