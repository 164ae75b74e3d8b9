import { act, screen, waitFor, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { LiveStore } from "../../live/store";
import { stubFetch, type FetchStub } from "../../test/fetchStub";
import { renderPage } from "../../test/render";
import { CIA402_RULES, DEVICE, INFO, LIVE, LOAD, RULES, TREE } from "./fixtures";
import type { PdoRules } from "./types";
import { PdoPage } from "./PdoPage";

afterEach(() => {
  vi.unstubAllGlobals();
  vi.useRealTimers();
});

function render(rules: PdoRules = RULES): FetchStub & { unmount: () => void } {
  const fetch = stubFetch({
    "GET /api/nodes/1/pdos/rules": rules,
    "GET /api/nodes/1/pdos": DEVICE,
    "GET /api/nodes/1/od": TREE,
    "GET /api/bus-load": LOAD,
    "GET /api/sync": { producing: false, period_us: null },
    "PUT /api/sync": { producing: true, period_us: 10_000 },
    "POST /api/nodes/1/nmt": { ...INFO, nmt_state: "operational" },
    "POST /api/nodes/1/pdos/live": { ...LIVE, pdos: [] },
    "GET /api/nodes/1/pdos/live": LIVE,
    "DELETE /api/nodes/1/pdos/live": { ...LIVE, active: false },
    "GET /api/nodes/1/pdos/export": () =>
      new Response("[1A00sub0]\nParameterValue=0x02\n", { status: 200 }),
  });
  const store = new LiveStore();
  store.upsertInfo(INFO);
  const { unmount } = renderPage(<PdoPage node={1} />, "/nodes/1/pdos", store);
  return { ...fetch, unmount };
}

async function editDraft(): Promise<void> {
  await userEvent.click(await screen.findByRole("button", { name: "Edit current mapping" }));
}

describe("PDO draft editing", () => {
  it("adds, reorders and removes objects, changing the layout", async () => {
    render();
    await editDraft();
    const rpdo = within(screen.getByRole("region", { name: "RPDO1 draft" }));
    await userEvent.type(rpdo.getByLabelText("Find an object to map into RPDO1"), "target");
    await userEvent.click(rpdo.getByRole("button", { name: "Add Target position 607Ah:00" }));
    const frame = (): string[] =>
      within(rpdo.getByRole("list", { name: "RPDO1 frame" }))
        .getAllByRole("listitem")
        .map((b) => b.textContent);
    expect(frame()[1]).toContain("Target position");
    expect(rpdo.getByText("draft: changed")).toBeTruthy();

    await userEvent.click(rpdo.getByRole("button", { name: "Move Target position earlier" }));
    expect(frame()[0]).toContain("Target position");
    await userEvent.click(rpdo.getByRole("button", { name: "Remove Target position from RPDO1" }));
    expect(frame()).toHaveLength(1);
    expect(rpdo.queryByText("draft: changed")).toBeNull();
  });

  it.each([
    ["6064", "Add Position actual value 6064h:00", "is read-only"],
    ["2100", "Add Digital input bit 2100h:00", "whole bytes only"],
  ])("refuses %s in an RPDO and says why", async (query, button, why) => {
    const fetch = render();
    await editDraft();
    const rpdo = within(screen.getByRole("region", { name: "RPDO1 draft" }));
    await userEvent.type(rpdo.getByLabelText("Find an object to map into RPDO1"), query);
    await userEvent.click(rpdo.getByRole("button", { name: button }));
    expect(rpdo.getByRole("alert").textContent).toContain(why);
    expect(
      within(rpdo.getByRole("list", { name: "RPDO1 frame" })).getAllByRole("listitem"),
    ).toHaveLength(1);
    expect(fetch.calls.some((c) => c.method !== "GET")).toBe(false);
  });

  it("refuses what would pass 64 bits", async () => {
    render(CIA402_RULES);
    await editDraft();
    const rpdo = within(screen.getByRole("region", { name: "RPDO1 draft" }));
    const search = rpdo.getByLabelText("Find an object to map into RPDO1");
    await userEvent.type(search, "607a");
    await userEvent.click(rpdo.getByRole("button", { name: "Add Target position 607Ah:00" }));
    await userEvent.click(rpdo.getByRole("button", { name: "Add Target position 607Ah:00" }));
    expect(rpdo.getByRole("alert").textContent).toBe(
      "Target position (607Ah:00) needs 32 bits; RPDO1 has 16 of 64 left.",
    );
    await userEvent.clear(search);
    await userEvent.type(search, "2100"); // 1 bit: fine on a bit-granular drive
    await userEvent.click(rpdo.getByRole("button", { name: "Add Digital input bit 2100h:00" }));
    expect(rpdo.queryByRole("alert")).toBeNull();
  });

  it("edits the communication parameter and words the transmission type", async () => {
    render(CIA402_RULES);
    await editDraft();
    const tpdo = within(screen.getByRole("region", { name: "TPDO1 draft" }));
    const type = tpdo.getByLabelText("TPDO1 transmission type");
    await userEvent.clear(type);
    await userEvent.type(type, "254");
    expect(tpdo.getByText("on change + event timer (manufacturer-specific event)")).toBeTruthy();
    const cob = tpdo.getByLabelText("TPDO1 COB-ID");
    await userEvent.clear(cob);
    await userEvent.type(cob, "0x281");
    expect(tpdo.getByText(/COB-ID 0x181 → 0x281/)).toBeTruthy();
    await userEvent.clear(tpdo.getByLabelText("TPDO1 inhibit time ms"));
    await userEvent.type(tpdo.getByLabelText("TPDO1 inhibit time ms"), "1.5");
    expect(tpdo.getByText(/inhibit 2.5 → 1.5 ms/)).toBeTruthy();
  });

  it("refuses a COB-ID the drive fixes and says why; the valid bit still changes", async () => {
    const fetch = render();
    await editDraft();
    const tpdo = within(screen.getByRole("region", { name: "TPDO1 draft" }));
    const cob = tpdo.getByLabelText<HTMLInputElement>("TPDO1 COB-ID");
    expect(cob.readOnly).toBe(true);
    expect(tpdo.getByText("fixed by the drive")).toBeTruthy();
    await userEvent.type(cob, "2");
    expect(tpdo.getByRole("alert").textContent).toBe(
      "This drive fixes the CAN id of PDOs 1–4 to the pre-defined set; only the valid bit can change.",
    );
    expect(cob.value).toBe("0x181");
    expect(tpdo.queryByText("draft: changed")).toBeNull();
    await userEvent.click(tpdo.getByRole("checkbox", { name: "Valid" }));
    expect(tpdo.queryByRole("alert")).toBeNull(); // said once, gone when the field is left
    expect(tpdo.getByText(/made invalid/)).toBeTruthy();
    expect(fetch.calls.some((c) => c.method !== "GET")).toBe(false);
  });

  it("lets a COB-ID past the fixed ones change", async () => {
    render({ ...RULES, fixed_cob_ids: 1 });
    await editDraft();
    const transmit = within(screen.getByRole("region", { name: "Transmit PDOs" }));
    await userEvent.click(transmit.getByRole("button", { name: "Show them" }));
    const tpdo = within(screen.getByRole("region", { name: "TPDO2 draft" }));
    const cob = tpdo.getByLabelText<HTMLInputElement>("TPDO2 COB-ID");
    expect(cob.readOnly).toBe(false);
    await userEvent.clear(cob);
    await userEvent.type(cob, "0x481");
    expect(tpdo.getByText(/COB-ID 0x281 → 0x481/)).toBeTruthy();
  });
});

describe("PDO live check and export", () => {
  it("starts the node, gives it SYNC and shows rate and decoded values", async () => {
    const fetch = render();
    await userEvent.click(await screen.findByRole("button", { name: "Produce SYNC" }));
    expect(await screen.findByText("SYNC produced every 10 ms")).toBeTruthy();
    await userEvent.click(screen.getByRole("button", { name: "Start node and watch PDOs" }));
    const table = await screen.findByRole("table", { name: "Received PDOs" });
    expect(await within(table).findByText("100/s")).toBeTruthy();
    expect(within(table).getByText("Position actual value")).toBeTruthy();
    expect(within(table).getByText("1234 inc")).toBeTruthy();
    // a value in words next to the number, the frame's bytes in the tooltip
    const status = within(table).getByText("Statusword").nextElementSibling;
    // a bit field in hex, as engineers read it; the number and bytes in the tooltip
    expect(status?.textContent).toBe("0x0250 · Switch on disabled");
    expect(status?.getAttribute("title")).toBe("6041h:00 bytes: 50 02 = 592");
    // a unit with a factor converted: 0.1 % steps read as %
    const torque = within(table).getByText("Torque actual value").nextElementSibling;
    expect(torque?.textContent).toBe("0.0 %");
    expect(torque?.getAttribute("title")).toBe("6077h:00 bytes: 00 00 = 0 (0.1 %)");
    expect(screen.getByTestId("pdo-drive-page").textContent).toMatch(/uses SDO/);
    // one frame: no rate yet
    expect(within(table).getByTestId("rate-641").textContent).toBe("—");
    expect(within(table).getByText("6061h:00").nextElementSibling?.textContent).toBe(
      "1 · Profile position",
    );
    // the node's TPDOs first; the master's RPDOs apart, the silent ones on one line
    const groups = within(table).getAllByRole("rowgroup");
    expect(groups.map((g) => g.getAttribute("aria-label"))).toEqual([
      null,
      "Sent by node 1",
      "Sent by the master",
    ]);
    const rows = within(groups[1] as HTMLElement).getAllByRole("row");
    expect(rows.map((r) => r.textContent.slice(0, 10))).toEqual([
      "Sent by no",
      "0x181TPDO1",
      "0x281TPDO2",
    ]);
    const master = within(groups[2] as HTMLElement);
    expect(
      master.getByText("None seen from the master: RPDO1 (0x201), RPDO2 (0x301)."),
    ).toBeTruthy();
    expect(master.queryByText("0/s")).toBeNull();
    const nmt = fetch.calls.find((c) => c.path === "/api/nodes/1/nmt");
    expect(JSON.parse(nmt?.body ?? "{}")).toEqual({ command: "start" });
    const sync = fetch.calls.find((c) => c.method === "PUT" && c.path === "/api/sync");
    expect(JSON.parse(sync?.body ?? "{}")).toEqual({ producing: true, period_us: 10_000 });

    // it keeps polling, and leaving the page stops the capture
    await waitFor(() =>
      expect(fetch.calls.filter((c) => c.path.endsWith("/live")).length).toBeGreaterThan(2),
    );
    fetch.unmount();
    await act(() => Promise.resolve());
    expect(fetch.calls.some((c) => c.method === "DELETE")).toBe(true);
  });

  it("shows the DCF fragment to read and download", async () => {
    const fetch = render();
    await userEvent.click(await screen.findByRole("button", { name: "DCF fragment" }));
    const dialog = within(await screen.findByRole("dialog"));
    expect(dialog.getByLabelText<HTMLTextAreaElement>("DCF fragment").value).toContain(
      "[1A00sub0]",
    );
    expect(dialog.getByRole("button", { name: "Download node1-pdos.dcf" })).toBeTruthy();
    expect(fetch.urls.some((u) => u.endsWith("/pdos/export?format=dcf"))).toBe(true);
  });
});
