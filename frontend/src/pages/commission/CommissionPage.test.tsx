import { screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { json, stubFetch } from "../../test/fetchStub";
import {
  identityDone,
  record,
  stopTestDone,
  storeVerifyLost,
} from "../../test/fixtures/commission";
import { renderPage } from "../../test/render";
import { CommissionPage } from "./CommissionPage";
import { serve } from "./fixtures";
import type { CommissioningRecord } from "./types";

afterEach(() => {
  vi.unstubAllGlobals();
});

const step = (name: string): HTMLElement =>
  screen.getByRole("listitem", { name: new RegExp(`^Step \\d: ${name}$`) });

describe("CommissionPage", () => {
  it("starts a record with the modes the drive supports and a title", async () => {
    let records: CommissioningRecord[] = [];
    const created = record({ title: "Axis X" });
    const stub = stubFetch({
      "GET /api/commissioning": () => records,
      "GET /api/nodes/3/drive": { node: 3, supported_modes: ["pp", "pv", "pt", "hm", "ip"] },
      "POST /api/nodes/3/commissioning": () => {
        records = [created];
        return json(created, 201);
      },
      "GET /api/commissioning/1": created,
    });
    renderPage(<CommissionPage node={3} />, "/nodes/3/commission");

    expect(await screen.findByRole("heading", { name: "Start commissioning node 3" })).toBeTruthy();
    const pp = await screen.findByRole("checkbox", { name: /PP Profile position/ });
    expect((pp as HTMLInputElement).checked).toBe(true);
    expect(
      screen.getByRole<HTMLInputElement>("checkbox", { name: /PT Profile torque/ }).checked,
    ).toBe(false);
    await userEvent.click(screen.getByRole("checkbox", { name: /PT Profile torque/ }));
    await userEvent.type(screen.getByRole("textbox", { name: /Title/ }), "Axis X");
    await userEvent.click(screen.getByRole("button", { name: "Start record" }));

    expect(await screen.findByRole("heading", { name: "Record #1: Axis X" })).toBeTruthy();
    const post = stub.calls.find((c) => c.method === "POST");
    expect(JSON.parse(post?.body ?? "{}")).toEqual({ modes: ["pp", "pv", "pt"], title: "Axis X" });
    const steps = within(screen.getByRole("list", { name: "Commissioning steps" }));
    expect(steps.getAllByRole("listitem").map((li) => li.getAttribute("aria-label"))).toEqual([
      "Step 1: Identity",
      "Step 2: Communication",
      "Step 3: Parameters",
      "Step 4: PDO mapping",
      "Step 5: Limits",
      "Step 6: Stop test",
      "Step 7: Test move",
      "Step 8: Homing",
      "Step 9: Store and verify",
    ]);
    expect(screen.getByText("In progress")).toBeTruthy();
    // pdo and homing run here, or are done by hand on their pages
    expect(within(step("PDO mapping")).getByRole("link", { name: /PDOs page/ })).toBeTruthy();
    expect(
      within(step("PDO mapping")).getByRole("button", { name: "Run PDO mapping" }),
    ).toBeTruthy();
    expect(
      within(step("Homing"))
        .getByRole("link", { name: /wizard on the Drive page/ })
        .getAttribute("href"),
    ).toBe("/nodes/3/drive");
  });

  it("resumes the newest record, runs identity and the stop test and shows their figures", async () => {
    let release: () => void = () => undefined;
    const stub = serve(record(), {
      identity: () => identityDone,
      stop_test: () =>
        new Promise((resolve) => {
          release = () => resolve(stopTestDone);
        }),
    });
    renderPage(<CommissionPage node={3} />, "/nodes/3/commission");

    await userEvent.click(await screen.findByRole("button", { name: "Run Identity" }));
    const identity = within(step("Identity"));
    expect(await identity.findByText("Done")).toBeTruthy();
    expect(identity.getByText("by local", { exact: false })).toBeTruthy();
    const values = identity.getByRole("table", { name: "Values read (Identity)" });
    const vendor = within(values).getByText("Vendor-ID").closest("tr") as HTMLElement;
    expect(within(vendor).getByText("0x0000026C")).toBeTruthy();
    expect(within(values).getByText("C5-E-SIM")).toBeTruthy();

    const stop = within(step("Stop test"));
    expect(stop.getByRole("note", { name: "The axis will move" }).textContent).toContain(
      "quick stop",
    );
    const speed = stop.getByRole("spinbutton", { name: "Stop test speed (rpm)" });
    expect((speed as HTMLInputElement).value).toBe("200");
    await userEvent.clear(speed);
    await userEvent.type(speed, "150");
    await userEvent.click(stop.getByRole("button", { name: "Run Stop test" }));
    expect(await stop.findByText(/Running the stop test/)).toBeTruthy();
    // one step at a time: the others cannot start meanwhile
    expect(
      within(step("Limits")).getByRole<HTMLButtonElement>("button", { name: "Run Limits" })
        .disabled,
    ).toBe(true);
    release();
    const figures = await stop.findByRole("table", { name: "Figures of Stop test" });
    const row = within(figures).getByText("quick stop stop time").closest("tr") as HTMLElement;
    expect(within(row).getByText("0.0038")).toBeTruthy();
    expect(within(row).getByText("s")).toBeTruthy();
    expect(stop.queryByText(/Running the stop test/)).toBeNull();
    const run = stub.calls.find((c) => c.path.endsWith("/stop_test/run"));
    expect(JSON.parse(run?.body ?? "{}")).toEqual({ speed_rpm: 150 });
  });

  it("runs homing with the chosen method and the pdo step with the recommended mapping", async () => {
    const stub = serve(
      record(),
      {
        homing: () => ({ ...record().steps[7], status: "done", by: "local" }),
        pdo: () => ({ ...record().steps[3], status: "done", by: "local" }),
      },
      {
        "GET /api/nodes/3/drive/homing-methods": () => [
          { method: 17, name: "Negative limit switch", description: "", path: [] },
          { method: 35, name: "Current position", description: "", path: [] },
        ],
      },
    );
    renderPage(<CommissionPage node={3} />, "/nodes/3/commission");

    const homing = within(await screen.findByRole("listitem", { name: "Step 8: Homing" }));
    expect(homing.getByRole("note", { name: "The axis will move" }).textContent).toContain(
      "homing",
    );
    const method = homing.getByRole<HTMLSelectElement>("combobox", { name: "Homing method" });
    expect(method.value).toBe("");
    await homing.findByRole("option", { name: "35: Current position" });
    await userEvent.selectOptions(method, "35");
    await userEvent.click(homing.getByRole("button", { name: "Run Homing" }));
    expect(await homing.findByText("Done")).toBeTruthy();
    const ran = stub.calls.find((c) => c.path.endsWith("/homing/run"));
    expect(JSON.parse(ran?.body ?? "{}")).toEqual({ method: 35 });

    const pdo = within(step("PDO mapping"));
    await userEvent.click(pdo.getByRole("checkbox", { name: /recommended mapping/ }));
    await userEvent.click(pdo.getByRole("button", { name: "Run PDO mapping" }));
    expect(await pdo.findByText("Done")).toBeTruthy();
    const applied = stub.calls.find((c) => c.path.endsWith("/pdo/run"));
    expect(JSON.parse(applied?.body ?? "{}")).toEqual({ apply: true });
  });

  it("skips a step only with a reason", async () => {
    const stub = serve(record());
    renderPage(<CommissionPage node={3} />, "/nodes/3/commission");

    await userEvent.click(await screen.findByRole("button", { name: "Skip Homing…" }));
    const homing = within(step("Homing"));
    const skip = homing.getByRole<HTMLButtonElement>("button", { name: "Skip step" });
    expect(skip.disabled).toBe(true);
    expect(homing.getByText("Give a reason to skip.")).toBeTruthy();
    await userEvent.type(
      homing.getByRole("textbox", { name: "Reason to skip Homing" }),
      "absolute encoder, no homing",
    );
    expect(skip.disabled).toBe(false);
    await userEvent.click(skip);

    expect(await homing.findByText("Skipped")).toBeTruthy();
    expect(homing.getByText("Reason: absolute encoder, no homing")).toBeTruthy();
    const put = stub.calls.find((c) => c.method === "PUT");
    expect(put?.path).toBe("/api/commissioning/1/steps/homing");
    expect(JSON.parse(put?.body ?? "{}")).toEqual({
      status: "skipped",
      reason: "absolute encoder, no homing",
    });
  });

  it("names each value a failed store_verify lost", async () => {
    serve(record(), { store_verify: () => storeVerifyLost });
    renderPage(<CommissionPage node={3} />, "/nodes/3/commission");

    await userEvent.click(await screen.findByRole("button", { name: "Run Store and verify" }));
    const verify = within(step("Store and verify"));
    expect(await verify.findByText("Failed")).toBeTruthy();
    expect(
      verify.getByText("Failed: not kept over the reset: 2006:08 PA-103: expected 5000, now 6000"),
    ).toBeTruthy();
    const lost = verify.getByRole("alert", { name: "Values lost over the reset" });
    expect(within(lost).getByText("2006:08 PA-103: expected 5000, now 6000")).toBeTruthy();
    const table = verify.getByRole("table", { name: "Not kept over the reset (Store and verify)" });
    expect(within(table).getByText("PA-103")).toBeTruthy();
  });

  it("says who holds the axis when a moving step is refused", async () => {
    serve(record(), {
      test_move: () =>
        json(
          {
            error: "held_by_other",
            message: "node 3 is controlled by Chrome tab 8933: take over control first",
            node: 3,
            holder: { client_id: "tab-8933", name: "Chrome tab 8933", since: 1_764_000_000 },
          },
          409,
        ),
    });
    renderPage(<CommissionPage node={3} />, "/nodes/3/commission");

    await userEvent.click(await screen.findByRole("button", { name: "Run Test move" }));
    const move = within(step("Test move"));
    expect(
      await move.findByText("node 3 is controlled by Chrome tab 8933: take over control first"),
    ).toBeTruthy();
    expect(move.getByText(/Chrome tab 8933 holds the axis/)).toBeTruthy();
    expect(move.getAllByRole("link", { name: "Drive page" })[0]?.getAttribute("href")).toBe(
      "/nodes/3/drive",
    );
  });

  it("offers the report as HTML, PDF and bundle links, and older records to choose", async () => {
    const newest = record({ id: 2, title: "after repair", status: "failed" });
    const older = record({ id: 1, title: "first", status: "done" });
    stubFetch({
      "GET /api/commissioning": [newest, older],
      "GET /api/commissioning/2": newest,
      "GET /api/commissioning/1": older,
    });
    renderPage(<CommissionPage node={3} />, "/nodes/3/commission");

    expect(await screen.findByRole("heading", { name: "Record #2: after repair" })).toBeTruthy();
    expect(screen.getByRole("link", { name: "Report (HTML)" }).getAttribute("href")).toBe(
      "/api/commissioning/2/report?format=html&lang=en",
    );
    expect(screen.getByRole("link", { name: "PDF" }).getAttribute("href")).toBe(
      "/api/commissioning/2/report?format=pdf&lang=en",
    );
    expect(screen.getByRole("link", { name: "Bundle (zip)" }).getAttribute("href")).toBe(
      "/api/commissioning/2/report?format=zip&lang=en",
    );
    await userEvent.selectOptions(screen.getByRole("combobox", { name: "Choose a record" }), "1");
    expect(await screen.findByRole("heading", { name: "Record #1: first" })).toBeTruthy();
  });
});
