import { screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import type { NodeInfo } from "../../api/types";
import { stubFetch } from "../../test/fetchStub";
import { mdiAlarm4 } from "../../test/fixtures/faults";
import { renderPage } from "../../test/render";
import { NetworkPage } from "./NetworkPage";

afterEach(() => {
  vi.unstubAllGlobals();
});

const node = (id: number, name: string, label: string): NodeInfo => ({
  node: id,
  name,
  vendor_id: 0x26c,
  product_code: 0xc5,
  profile: "cia402",
  profile_label: label,
  nmt_state: "pre-operational",
  online: true,
  heartbeat_age_ms: 40,
  od_source: "profile",
  od_filename: "cia402/drive.eds",
  od_warnings: 0,
});

describe("NetworkPage", () => {
  it("lists the nodes a scan returns, with identity and live state", async () => {
    const fetch = stubFetch({
      "GET /api/bus/interfaces": [
        { name: "virtual", label: "Virtual", needs_channel: false, example_channel: "" },
      ],
      "POST /api/scan": {
        nodes: [node(1, "DVS_CANOPEN", "MDi-S1-C"), node(3, "C5-E-SIM", "CiA 402")],
        duration_ms: 57,
      },
      "GET /api/nodes/1/heartbeat": { producer_ms: 100 },
      "GET /api/nodes/3/heartbeat": { producer_ms: 0 },
      "GET /api/events": { events: [], next: null },
    });
    const { store } = renderPage(<NetworkPage />);
    expect(screen.getByText(/No nodes known yet/)).toBeTruthy();

    await userEvent.click(screen.getByRole("button", { name: "Scan" }));

    expect(await screen.findByText("Found 2 nodes in 57 ms")).toBeTruthy();
    const rows = screen.getAllByRole("row").slice(1); // skip the header row
    expect(rows).toHaveLength(2);
    const first = within(rows[0] as HTMLElement);
    expect(first.getByText("DVS_CANOPEN")).toBeTruthy();
    expect(first.getByText("MDi-S1-C")).toBeTruthy();
    expect(first.getByText("0x0000026C")).toBeTruthy();
    expect(first.getByText("Pre-operational")).toBeTruthy();
    expect(await screen.findByDisplayValue("100")).toBeTruthy(); // heartbeat producer of node 1
    expect(JSON.parse(fetch.calls.find((c) => c.path === "/api/scan")?.body ?? "{}")).toEqual({
      sdo_sweep: true,
      timeout_ms: 50,
    });

    // A live update re-renders the state cell without another request.
    store.apply({
      type: "nodes",
      nodes: [{ node: 1, nmt_state: "operational", online: true, heartbeat_age_ms: 12 }],
    });
    expect(await first.findByText("Operational")).toBeTruthy();
    expect(first.getByText("12 ms")).toBeTruthy();
  });

  it("says where a gone node's drive answers now and forgets it", async () => {
    const ghost = { ...node(1, "DVS_CANOPEN", "MDi-S1-C"), online: false, moved_to: 5 };
    let nodes = [ghost, node(5, "DVS_CANOPEN", "MDi-S1-C")];
    const fetch = stubFetch({
      "GET /api/bus/interfaces": [],
      "GET /api/events": { events: [], next: null },
      "POST /api/scan": () => ({ nodes, duration_ms: 40 }),
      "GET /api/nodes": () => nodes,
      "GET /api/nodes/1/heartbeat": { producer_ms: 0 },
      "GET /api/nodes/5/heartbeat": { producer_ms: 0 },
      "DELETE /api/nodes/1": () => {
        nodes = nodes.slice(1);
        return new Response(null, { status: 204 });
      },
    });
    renderPage(<NetworkPage />);
    await userEvent.click(screen.getByRole("button", { name: "Scan" }));
    const gone = await screen.findByText(/Gone: the drive answers as/);
    expect(gone.textContent).toBe("Gone: the drive answers as node 5 now. Forget");
    expect(within(gone).getByRole("link", { name: "node 5" }).getAttribute("href")).toBe(
      "/nodes/5/parameters",
    );
    await userEvent.click(screen.getByRole("button", { name: "Forget node 1" }));
    await vi.waitFor(() => expect(screen.getAllByRole("row").slice(1)).toHaveLength(1));
    expect(fetch.calls.some((c) => c.method === "DELETE" && c.path === "/api/nodes/1")).toBe(true);
    expect(screen.queryByText(/Gone:/)).toBeNull();
  });

  it("lists revision, serial and firmware, lights a node in fault, and asks for heartbeats", async () => {
    const mdi: NodeInfo = {
      ...node(1, "DVS_CANOPEN", "MDi-S1-C"),
      revision: 1,
      serial: 0x53440001,
      software_version: "V1.01",
      hardware_version: "V1.0",
      heartbeat_age_ms: null,
    };
    stubFetch({
      "GET /api/bus/interfaces": [],
      "GET /api/events": { events: [], next: null },
      "POST /api/scan": { nodes: [mdi], duration_ms: 40 },
      "GET /api/nodes/1/heartbeat": { producer_ms: 0 },
    });
    const { store } = renderPage(<NetworkPage />);
    await userEvent.click(screen.getByRole("button", { name: "Scan" }));
    expect(await screen.findByText("rev 0x00000001 · SN 0x53440001")).toBeTruthy();
    expect(screen.getByText("FW V1.01 · HW V1.0")).toBeTruthy();
    expect(screen.getByRole("note", { name: "No heartbeats" }).textContent).toContain(
      "No node sends a heartbeat",
    );
    expect(screen.queryByRole("link", { name: /in fault/ })).toBeNull();
    store.setActiveFaults([mdiAlarm4({ error_register: 0x81 })], store.faultVersion());
    const lamp = await screen.findByRole("link", {
      name: "Node 1 in fault (1001h = 0x81): open its faults",
    });
    expect(lamp.getAttribute("href")).toBe("/nodes/1/faults");
  });

  it("shows the bus state and counters from the live store", async () => {
    stubFetch({ "GET /api/bus/interfaces": [], "GET /api/events": { events: [], next: null } });
    const { store } = renderPage(<NetworkPage />);
    store.apply({
      type: "bus",
      bus: {
        state: "error",
        interface: "socketcand",
        channel: "can0",
        bitrate: 250000,
        simulated: false,
        error: "connection refused",
        rx_frames: 1234,
        tx_frames: 5,
        error_frames: 2,
        bus_errors: 1,
        reconnects: 3,
        since: null,
      },
    });
    expect(await screen.findByText("Error")).toBeTruthy();
    expect(screen.getByRole("alert").textContent).toBe("connection refused");
    expect(screen.getByText("1,234")).toBeTruthy();
    const facts = screen.getByText("Bitrate", { selector: "dt" }).nextElementSibling;
    expect(facts?.textContent).toBe("250 kbit/s");
  });

  it("says when the drives booted before ServoDesk listened, with the last boot-up it knows", async () => {
    stubFetch({
      "GET /api/bus/interfaces": [],
      "POST /api/scan": { nodes: [node(1, "DVS_CANOPEN", "MDi-S1-C")], duration_ms: 40 },
      "GET /api/nodes/1/heartbeat": { producer_ms: 0 },
      "GET /api/events": (request: Request) => {
        const query = new URL(request.url).searchParams;
        const other = {
          id: 7,
          time: 1795757857.3,
          kind: "boot-up",
          node: 1,
          message: "node 1 booted",
          data: {},
          bus: "socketcan can0",
        };
        const events = query.get("kind") === "boot-up" && query.get("all_buses") ? [other] : [];
        return { events, next: null };
      },
    });
    renderPage(<NetworkPage />);
    await userEvent.click(screen.getByRole("button", { name: "Scan" }));
    const note = await screen.findByRole("note", { name: "No boot-up seen" });
    expect(note.textContent).toMatch(
      /^No boot-up on this bus since ServoDesk started listening: the drives booted before it\. The last boot-up ServoDesk knows of: node 1 at \d\d:\d\d:\d\d\.\d+ \(socketcan can0\)\.$/,
    );
  });
});
