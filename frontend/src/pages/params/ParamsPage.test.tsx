import { screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { json, stubFetch } from "../../test/fetchStub";
import { renderPage } from "../../test/render";
import { PA103, PA106 } from "./fixtures";
import { ParamsPage } from "./ParamsPage";

afterEach(() => {
  vi.unstubAllGlobals();
});

const EMPTY_DCF_ROUTES = {};

describe("ParamsPage", () => {
  it("renders the catalogue and shows the server's message after a write", async () => {
    const fetch = stubFetch({
      ...EMPTY_DCF_ROUTES,
      "GET /api/nodes/1/params": [PA106, PA103],
      "PUT /api/nodes/1/params/PA-106": {
        param: { ...PA106, value: 4, pending: true },
        message:
          "written; the drive talks at the new bitrate after a store and a reset, and the bus must follow it: use Change bitrate…, which stores, resets and says how to reconnect",
        requires_reset: true,
        requires_store: true,
      },
    });
    renderPage(<ParamsPage node={1} />, "/nodes/1/parameters");

    expect(await screen.findByRole("rowheader", { name: "PA-106" })).toBeTruthy();
    expect(screen.getByRole("rowheader", { name: "PA-103" })).toBeTruthy();
    expect(screen.getAllByText("after reset").length).toBeGreaterThan(0);

    await userEvent.selectOptions(screen.getByLabelText("PA-106", { selector: "select" }), "4");
    await userEvent.click(screen.getByRole("button", { name: "Write PA-106" }));

    expect(await screen.findByText(/use Change bitrate…/)).toBeTruthy();
    // written, not in effect: the row says so until the drive boots again
    const row = screen.getByRole("rowheader", { name: "PA-106" }).closest("tr") as HTMLElement;
    expect(within(row).getByText("pending until reset")).toBeTruthy();
    const put = fetch.calls.find((c) => c.method === "PUT");
    expect(put?.path).toBe("/api/nodes/1/params/PA-106");
    expect(JSON.parse(put?.body ?? "{}")).toEqual({ value: 4 });
  });

  it("refuses an out-of-range value before sending it", async () => {
    const fetch = stubFetch({ "GET /api/nodes/1/params": [PA103] });
    renderPage(<ParamsPage node={1} />, "/nodes/1/parameters");
    const input = await screen.findByLabelText("PA-103", { selector: "input" });
    await userEvent.clear(input);
    await userEvent.type(input, "7000");
    await userEvent.click(screen.getByRole("button", { name: "Write PA-103" }));
    expect(screen.getByRole("alert").textContent).toBe("7000 is outside 0…6000");
    expect(fetch.calls.some((c) => c.method === "PUT")).toBe(false);
  });

  it("replaces a row's earlier success with the failure of a new attempt", async () => {
    stubFetch({
      "GET /api/nodes/1/params": [PA103, PA106],
      "PUT /api/nodes/1/params/PA-103": {
        param: { ...PA103, value: 5000 },
        message: "applied",
        requires_reset: false,
        requires_store: false,
      },
    });
    renderPage(<ParamsPage node={1} />, "/nodes/1/parameters");
    const input = await screen.findByLabelText("PA-103", { selector: "input" });
    await userEvent.clear(input);
    await userEvent.type(input, "5000");
    await userEvent.click(screen.getByRole("button", { name: "Write PA-103" }));
    expect(await screen.findByText("PA-103: applied")).toBeTruthy();

    await userEvent.clear(input);
    await userEvent.type(input, "7000");
    await userEvent.click(screen.getByRole("button", { name: "Write PA-103" }));
    expect(screen.getByRole("alert").textContent).toBe("7000 is outside 0…6000");
    expect(screen.queryByText("PA-103: applied")).toBeNull();
    expect(
      screen.getAllByRole("row").filter((row) => row.textContent.includes("7000 is")),
    ).toHaveLength(1); // one note row, PA-103's own
  });

  it("offers to set a Stopped node Pre-operational and reads the parameters again", async () => {
    let stopped = true;
    const fetch = stubFetch({
      "GET /api/nodes/1/params": () =>
        stopped
          ? json(
              {
                error: "node_stopped",
                message:
                  "node 1 is Stopped: SDO is not available in that state — set it Pre-operational or Operational",
                node: 1,
              },
              409,
            )
          : [PA103],
      "POST /api/nodes/1/nmt": () => {
        stopped = false;
        return { node: 1, nmt_state: "pre-operational" };
      },
    });
    renderPage(<ParamsPage node={1} />, "/nodes/1/parameters");
    expect((await screen.findByRole("alert")).textContent).toContain("node 1 is Stopped");
    await userEvent.click(screen.getByRole("button", { name: "Set node 1 Pre-operational" }));
    expect(await screen.findByRole("rowheader", { name: "PA-103" })).toBeTruthy();
    expect(fetch.calls.filter((c) => c.method === "POST")).toHaveLength(1);
  });

  it("shows an SDO abort where the write happened", async () => {
    stubFetch({
      "GET /api/nodes/1/params": [PA103],
      "PUT /api/nodes/1/params/PA-103": json(
        {
          error: "sdo_abort",
          message: "Value of parameter written too high",
          abort_code: "0x06090031",
        },
        409,
      ),
    });
    renderPage(<ParamsPage node={1} />, "/nodes/1/parameters");
    const input = await screen.findByLabelText("PA-103", { selector: "input" });
    await userEvent.clear(input);
    await userEvent.type(input, "5000");
    await userEvent.click(screen.getByRole("button", { name: "Write PA-103" }));
    expect((await screen.findByRole("alert")).textContent).toBe(
      "0x06090031 — Value of parameter written too high",
    );
  });

  it("explains a node without a catalogue and keeps the parameter-set panel", async () => {
    stubFetch({ "GET /api/nodes/9/params": [] });
    renderPage(<ParamsPage node={9} />, "/nodes/9/parameters");
    expect(await screen.findByText("No parameter catalogue")).toBeTruthy();
    expect(screen.getByRole("button", { name: "Save DCF" })).toBeTruthy();
    expect(screen.queryByRole("button", { name: "Store parameters" })).toBeNull();
  });

  it("lists what a DCF load wrote but asks to check (a synchronous PDO without SYNC)", async () => {
    const warning =
      "RPDO1 is synchronous (every SYNC) but no SYNC is produced or heard: it is written for the machine's controller";
    const preview = {
      rows: [],
      read_only: [],
      identity: { matches: true, file: "vendor 0x26C", device: "vendor 0x26C", checked: true },
      confirm: [],
    };
    stubFetch({
      "GET /api/nodes/3/params": [],
      "POST /api/nodes/3/compare": preview,
      "POST /api/nodes/3/dcf": {
        identity: preview.identity,
        written: 12,
        skipped: 0,
        failed: [],
        differences: [],
        warnings: [warning],
      },
    });
    renderPage(<ParamsPage node={3} />, "/nodes/3/parameters");
    await userEvent.upload(await screen.findByLabelText("Load DCF…"), new File(["x"], "plc.dcf"));
    await userEvent.click(await screen.findByRole("button", { name: "Write the set anyway" }));
    const check = await screen.findByRole("list", { name: "Written, but check" });
    expect(check.textContent).toBe(warning);
    expect(screen.getByText(/Written 12, skipped 0, failed 0/)).toBeTruthy();
  });
});
