import { act, screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, beforeEach, describe, expect, it, vi } from "vitest";

import { LiveStore, type LinkStatus } from "../../live/store";
import { json, stubFetch, type FetchStub } from "../../test/fetchStub";
import { cia402Fault, mdiAlarm4 } from "../../test/fixtures/faults";
import { renderPage } from "../../test/render";
import { ERROR_CODE_READ_MS } from "./ActiveFaultCard";
import { FaultsPage } from "./FaultsPage";
import type { Fault, NodeFaults } from "./types";
import { HISTORY_REFETCH_MS } from "./useFaultHistory";

afterEach(() => {
  vi.unstubAllGlobals();
});

const errorCodeLine = (): string | null | undefined =>
  document.querySelector(".error-code-line")?.textContent;

const sdo603f = (value: number) => ({
  node: 1,
  index: 0x603f,
  subindex: 0,
  value,
  text: String(value),
  raw_hex: "",
});

describe("FaultsPage", () => {
  it("shows the active fault in words, resets it and lists the history", async () => {
    let faults: NodeFaults = {
      active: mdiAlarm4(),
      history: [mdiAlarm4({ time: 1_764_000_000 }), mdiAlarm4({ time: 1_764_000_000.5 })],
      total: 5,
    };
    const stub = stubFetch({
      "GET /api/nodes/1/faults": () => faults,
      "GET /api/nodes/1/sdo/603F/00": () => sdo603f(faults.active ? 4 : 0),
      "GET /api/nodes/1/faults/device-history": json(
        {
          error: "sdo_abort",
          message: "Object does not exist in the object dictionary",
          abort_code: "0x06020000",
        },
        502,
      ),
      "POST /api/nodes/1/faults/reset": () => {
        faults = { ...faults, active: null };
        return {
          node: 1,
          ok: true,
          message: "fault reset: node 1 went from Fault to Switch on disabled",
          state_before: "Fault",
          state_after: "Switch on disabled",
          statusword_hex: "0x0250",
          active: null,
        };
      },
    });
    renderPage(<FaultsPage node={1} />, "/nodes/1/faults");

    const active = await screen.findByRole("heading", {
      name: "In fault: alarm 4 位置超差 Following error",
    });
    const card = within(active.closest("section") as HTMLElement);
    expect(card.getByText("位置超差")).toBeTruthy();
    expect(card.getByText("the drive's own alarm table")).toBeTruthy();
    expect(card.getByText("gain, load, 6065h.")).toBeTruthy();
    expect(card.getByText("MDi-S1-C CANopen manual §4.1.")).toBeTruthy();
    expect(card.getByText("not in this drive's EMCY")).toBeTruthy();
    expect(card.getByText("04 00")).toBeTruthy();
    await vi.waitFor(() =>
      expect(errorCodeLine()).toBe(
        "Error code 603Fh on the drive: 0x0004: alarm 4 位置超差 Following error",
      ),
    );
    expect(
      await screen.findByText("Node 1 keeps no error history of its own (no 1003h)."),
    ).toBeTruthy();

    expect(screen.getByText("5 EMCYs stored, the newest 2 shown")).toBeTruthy();
    const history = screen.getByRole("table", { name: "Fault history" });
    expect(within(history).getAllByRole("row")).toHaveLength(3);
    expect(within(history).getAllByText("Switch on disabled → Fault")).toHaveLength(2);
    await userEvent.click(within(history).getAllByRole("row")[1] as HTMLElement);
    expect(screen.getByLabelText("Selected fault").textContent).toContain("04 00");

    await userEvent.click(card.getByRole("button", { name: "Fault reset" }));
    expect(
      await screen.findByText("fault reset: node 1 went from Fault to Switch on disabled"),
    ).toBeTruthy();
    expect(await screen.findByRole("heading", { name: "No active fault" })).toBeTruthy();
    await vi.waitFor(() =>
      expect(errorCodeLine()).toBe("Error code 603Fh on the drive: 0x0000: no error"),
    );
    expect(stub.calls.filter((c) => c.method === "POST")).toHaveLength(1);
  });

  it("resets as this tab, and names the holder when another client controls the drive", async () => {
    const sent: (string | null)[] = [];
    let held = false;
    stubFetch({
      "GET /api/nodes/1/faults": () => ({ active: mdiAlarm4(), history: [], total: 0 }),
      "GET /api/nodes/1/sdo/603F/00": () => sdo603f(4),
      "GET /api/nodes/1/faults/device-history": json({ count: 0, entries: [] }),
      "POST /api/nodes/1/faults/reset": (request: Request) => {
        sent.push(request.headers.get("X-Client-Id"));
        if (!held) {
          return {
            node: 1,
            ok: true,
            message: "fault reset: node 1 went from Fault to Switch on disabled",
            state_before: "Fault",
            state_after: "Switch on disabled",
            statusword_hex: "0x0250",
            active: null,
          };
        }
        return json(
          {
            error: "held_by_other",
            message: "node 1 is controlled by Chrome tab 8933: take over control first",
            node: 1,
            holder: { client_id: "other", name: "Chrome tab 8933", since: 1 },
          },
          409,
        );
      },
    });
    renderPage(<FaultsPage node={1} />, "/nodes/1/faults");
    const reset = await screen.findByRole("button", { name: "Fault reset" });
    await userEvent.click(reset);
    await screen.findByText("fault reset: node 1 went from Fault to Switch on disabled");
    held = true;
    await userEvent.click(reset);
    const refusal = await screen.findByRole("alert");
    expect(refusal.textContent).toBe(
      "Not reset: node 1 is controlled by Chrome tab 8933. Take over control on its Drive page, then reset here.",
    );
    expect(within(refusal).getByRole("link", { name: "its Drive page" }).getAttribute("href")).toBe(
      "/nodes/1/drive",
    );
    expect(sent).toHaveLength(2);
    expect(sent.every((id) => id !== null && id.length > 0)).toBe(true); // this tab's id
  });

  it("reads the drive's 1003h and clears it only after confirming", async () => {
    let entries = [
      { number: 1, value_hex: "0x00008611", fault: cia402Fault({ error_register: null }) },
    ];
    const stub = stubFetch({
      "GET /api/nodes/3/faults": { active: null, history: [], total: 0 },
      "GET /api/nodes/3/sdo/603F/00": { ...sdo603f(0), node: 3 },
      "GET /api/nodes/3/faults/device-history": () => ({
        node: 3,
        count: entries.length,
        entries,
        error_code: null,
      }),
      "DELETE /api/nodes/3/faults/device-history": () => {
        entries = [];
        return { node: 3, message: "node 3: error history 1003h cleared" };
      },
    });
    renderPage(<FaultsPage node={3} />, "/nodes/3/faults");

    const table = await screen.findByRole("table", { name: "Drive's error history" });
    expect(within(table).getByText("0x00008611")).toBeTruthy();
    expect(screen.getByText("No EMCY from this node on this bus yet.")).toBeTruthy();

    await userEvent.click(screen.getByRole("button", { name: "Clear history…" }));
    const dialog = screen.getByRole("dialog");
    expect(dialog.textContent).toContain("cannot be undone");
    expect(stub.calls.some((c) => c.method === "DELETE")).toBe(false);
    await userEvent.click(within(dialog).getByRole("button", { name: "Clear 1003h" }));

    expect(await screen.findByText("node 3: error history 1003h cleared")).toBeTruthy();
    expect(await screen.findByText("The drive's history is empty.")).toBeTruthy();
    const del = stub.calls.find((c) => c.method === "DELETE");
    expect(JSON.parse(del?.body ?? "{}")).toEqual({ confirm: true });
  });

  it("shows error register bits and manufacturer bytes of a CiA 301 EMCY", async () => {
    stubFetch({
      "GET /api/nodes/3/faults": { active: cia402Fault(), history: [cia402Fault()], total: 1 },
      "GET /api/nodes/3/sdo/603F/00": { ...sdo603f(0x8611), node: 3 },
      "GET /api/nodes/3/faults/device-history": {
        node: 3,
        count: 0,
        entries: [],
        error_code: null,
      },
    });
    renderPage(<FaultsPage node={3} />, "/nodes/3/faults");
    const heading = await screen.findByRole("heading", {
      name: "In fault: 0x8611 Following error",
    });
    const card = within(heading.closest("section") as HTMLElement);
    expect(card.getByText("21h: generic, device profile")).toBeTruthy();
    expect(card.getByText("00 00 00 00 00")).toBeTruthy();
    expect(card.getByText("CiA 402 (drive profile)")).toBeTruthy();
    await vi.waitFor(() => expect(errorCodeLine()).toContain("0x8611: Following error"));
  });

  it("lists this bus's faults, and other buses' too when asked, each naming its bus", async () => {
    const mine = { ...mdiAlarm4({ time: 1_764_000_000 }), bus: "socketcan can0" };
    const other = { ...mdiAlarm4({ time: 1_763_000_000 }), bus: "socketcan can1" };
    const stub = stubFetch({
      "GET /api/nodes/1/faults": (request: Request) =>
        new URL(request.url).searchParams.get("all_buses") === "true"
          ? { active: null, history: [mine, other], total: 2 }
          : { active: null, history: [mine], total: 1 },
      "GET /api/nodes/1/sdo/603F/00": sdo603f(0),
      "GET /api/nodes/1/faults/device-history": {
        node: 1,
        count: 0,
        entries: [],
        error_code: null,
      },
    });
    renderPage(<FaultsPage node={1} />, "/nodes/1/faults");

    expect(await screen.findByText("1 EMCY stored")).toBeTruthy();
    const history = screen.getByRole("table", { name: "Fault history" });
    expect(within(history).queryByRole("columnheader", { name: "Bus" })).toBeNull();
    await userEvent.click(screen.getByRole("checkbox", { name: "Other buses too" }));
    expect(await screen.findByText("2 EMCYs stored")).toBeTruthy();
    const every = screen.getByRole("table", { name: "Fault history" });
    expect(within(every).getByText("socketcan can1")).toBeTruthy();
    expect(stub.urls.some((url) => url.includes("all_buses=true"))).toBe(true);
  });
});

const OPEN: LinkStatus = { state: "open", attempt: 0, retryAt: null };
const PAUSED = /^Live updates paused/;
const IN_FAULT = "In fault: alarm 4 位置超差 Following error";

const wait = (ms: number): Promise<void> =>
  act(async () => {
    await vi.advanceTimersByTimeAsync(ms);
  });

/** GETs of the node's faults (the history, and formerly the 2 s poll). */
const faultReads = (stub: FetchStub): number =>
  stub.calls.filter((c) => c.method === "GET" && c.path === "/api/nodes/1/faults").length;

/** The server side of node 1: what GET …/faults answers now (tests change it as the drive
 * would); 603Fh follows the active fault. */
function serveNode1(server: { faults: NodeFaults }): FetchStub {
  return stubFetch({
    "GET /api/nodes/1/faults": () => server.faults,
    "GET /api/nodes/1/sdo/603F/00": () => sdo603f(server.faults.active ? 4 : 0),
    "GET /api/nodes/1/faults/device-history": {
      node: 1,
      count: 0,
      entries: [],
      error_code: null,
      supported: false,
    },
  });
}

/** The page on an open live channel, once its first reads are shown (603Fh read before the
 * active fault was known is read again once it is). */
async function openPage(server: { faults: NodeFaults }): Promise<{
  stub: FetchStub;
  store: LiveStore;
}> {
  const stub = serveNode1(server);
  const store = new LiveStore();
  store.setLink(OPEN);
  renderPage(<FaultsPage node={1} />, "/nodes/1/faults", store);
  await screen.findByRole("heading", { name: server.faults.active ? IN_FAULT : "No active fault" });
  await wait(ERROR_CODE_READ_MS);
  await vi.waitFor(() => expect(errorCodeLine()).toMatch(/0x000[04]/));
  return { stub, store };
}

const fault = (store: LiveStore, node: number, value: Fault | null): void =>
  act(() => store.apply({ type: "fault", node, fault: value }));

describe("FaultsPage on the live channel", () => {
  beforeEach(() => {
    // fake timers that also run on their own, so the page's reads can be awaited
    vi.useFakeTimers({ shouldAdvanceTime: true });
  });

  afterEach(() => {
    vi.useRealTimers();
  });

  it("shows the channel's fault at once, reads the history once after it, drops it when cleared", async () => {
    const server = { faults: { active: null, history: [], total: 0 } as NodeFaults };
    const { stub, store } = await openPage(server);
    expect(faultReads(stub)).toBe(1);
    expect(screen.queryByText(PAUSED)).toBeNull();

    // an EMCY: the channel's `fault` message; no REST read gives it
    server.faults = { active: mdiAlarm4(), history: [mdiAlarm4()], total: 1 };
    fault(store, 1, mdiAlarm4({ state_after: null }));
    const heading = screen.getByRole("heading", { name: IN_FAULT });
    expect(within(heading.closest("section") as HTMLElement).getByText("04 00")).toBeTruthy();
    expect(faultReads(stub)).toBe(1);
    expect(screen.getByText("No EMCY from this node on this bus yet.")).toBeTruthy();
    // … then the same fault with the state read after it, once it is stored
    fault(store, 1, mdiAlarm4());
    await vi.waitFor(() =>
      expect(errorCodeLine()).toBe(
        "Error code 603Fh on the drive: 0x0004: alarm 4 位置超差 Following error",
      ),
    );

    // the history is read once for the burst, a moment after its first message
    await wait(HISTORY_REFETCH_MS);
    const history = await screen.findByRole("table", { name: "Fault history" });
    expect(within(history).getAllByRole("row")).toHaveLength(2);
    expect(within(history).getByText("Switch on disabled → Fault")).toBeTruthy();
    expect(screen.getByText("1 EMCY stored")).toBeTruthy();
    expect(faultReads(stub)).toBe(1 + 1);

    // another node's fault is not this page's: nothing read
    fault(store, 2, mdiAlarm4({ node: 2 }));
    await wait(10_000);
    expect(faultReads(stub)).toBe(2);

    // cleared (error-reset EMCY): gone at once, as from the banner
    server.faults = { ...server.faults, active: null };
    fault(store, 1, null);
    expect(screen.getByRole("heading", { name: "No active fault" })).toBeTruthy();
    await vi.waitFor(() =>
      expect(errorCodeLine()).toBe("Error code 603Fh on the drive: 0x0000: no error"),
    );
    await wait(HISTORY_REFETCH_MS);
    await vi.waitFor(() => expect(faultReads(stub)).toBe(3));
    expect(screen.getByRole("heading", { name: "No active fault" })).toBeTruthy();
    expect(screen.getByText("1 EMCY stored")).toBeTruthy(); // the history keeps it
  });

  it("polls nothing on a timer", async () => {
    const server = { faults: { active: mdiAlarm4(), history: [mdiAlarm4()], total: 1 } };
    const { stub } = await openPage(server);
    const requests = stub.calls.length;
    expect(faultReads(stub)).toBe(1);
    await wait(10_000);
    expect(stub.calls.length).toBe(requests); // no GET of …/faults, 603Fh or 1003h
  });

  it("says when the channel is down and reads once when it is back, not polling meanwhile", async () => {
    const server = { faults: { active: null, history: [], total: 0 } as NodeFaults };
    const { stub, store } = await openPage(server);

    act(() => store.setLink({ state: "closed", attempt: 1, retryAt: Date.now() + 1000 }));
    expect(screen.getByText(PAUSED).textContent).toContain("read again when it is back");
    // what happens on the drive while the page cannot hear it
    server.faults = { active: mdiAlarm4(), history: [mdiAlarm4()], total: 1 };
    await wait(10_000);
    expect(faultReads(stub)).toBe(1);
    act(() => store.setLink({ state: "connecting", attempt: 1, retryAt: null }));
    expect(screen.getByText(PAUSED)).toBeTruthy();

    act(() => store.setLink(OPEN));
    expect(screen.queryByText(PAUSED)).toBeNull();
    await wait(HISTORY_REFETCH_MS);
    expect(await screen.findByRole("heading", { name: IN_FAULT })).toBeTruthy();
    expect(await screen.findByText("1 EMCY stored")).toBeTruthy();
    expect(faultReads(stub)).toBe(2);
    await wait(10_000);
    expect(faultReads(stub)).toBe(2);
  });

  it("keeps a fault message newer than the REST answer it raced with", async () => {
    const server = { faults: { active: null, history: [], total: 0 } as NodeFaults };
    let answer: (() => void) | null = null;
    const stub = stubFetch({
      "GET /api/nodes/1/faults": () =>
        // the answer was made before the EMCY, and arrives after its message
        new Promise((resolve) => {
          const made = { ...server.faults };
          answer = () => resolve(made);
        }),
      "GET /api/nodes/1/sdo/603F/00": () => sdo603f(4),
      "GET /api/nodes/1/faults/device-history": { node: 1, count: 0, entries: [] },
    });
    const store = new LiveStore();
    store.setLink(OPEN);
    renderPage(<FaultsPage node={1} />, "/nodes/1/faults", store);
    await vi.waitFor(() => expect(answer).not.toBeNull());
    fault(store, 1, mdiAlarm4());
    act(() => answer?.());
    await vi.waitFor(() => expect(screen.getByText("No EMCY from this node on this bus yet.")));
    expect(screen.getByRole("heading", { name: IN_FAULT })).toBeTruthy();
    expect(faultReads(stub)).toBe(1);
  });

  it("loads older history entries on demand", async () => {
    const stored = Array.from({ length: 150 }, (_, i) => mdiAlarm4({ time: 1_764_000_000 - i }));
    const stub = stubFetch({
      "GET /api/nodes/1/faults": (request: Request) => {
        const limit = Number(new URL(request.url).searchParams.get("limit") ?? 100);
        return { active: null, history: stored.slice(0, limit), total: stored.length };
      },
      "GET /api/nodes/1/sdo/603F/00": sdo603f(0),
      "GET /api/nodes/1/faults/device-history": { node: 1, count: 0, entries: [] },
    });
    renderPage(<FaultsPage node={1} />, "/nodes/1/faults");
    expect(await screen.findByText("150 EMCYs stored, the newest 100 shown")).toBeTruthy();
    await userEvent.click(screen.getByRole("button", { name: "Older…" }));
    expect(await screen.findByText("150 EMCYs stored")).toBeTruthy();
    const history = screen.getByRole("table", { name: "Fault history" });
    expect(within(history).getAllByRole("row")).toHaveLength(151);
    expect(screen.queryByRole("button", { name: "Older…" })).toBeNull();
    expect(stub.urls.filter((url) => url.includes("/faults?")).at(-1)).toContain("limit=200");
  });
});
