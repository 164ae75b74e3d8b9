import { screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { LiveStore } from "../../live/store";
import { json, stubFetch, type Handler } from "../../test/fetchStub";
import { renderPage } from "../../test/render";
import { DEVICE, INFO, LOAD, RECOMMENDED, TREE } from "./fixtures";
import { PdoPage } from "./PdoPage";

afterEach(() => {
  vi.unstubAllGlobals();
});

const BASE = {
  "GET /api/nodes/1/pdos": DEVICE,
  "GET /api/nodes/1/od": TREE,
  "GET /api/bus-load": { ...LOAD, percent: 12, over_threshold: false },
  "GET /api/sync": { producing: false, period_us: null },
};

function render(routes: Record<string, Handler | object> = {}): ReturnType<typeof stubFetch> {
  const fetch = stubFetch({ ...BASE, ...routes });
  const store = new LiveStore();
  store.upsertInfo(INFO);
  renderPage(<PdoPage node={1} />, "/nodes/1/pdos", store);
  return fetch;
}

async function recommendPp(): Promise<void> {
  await userEvent.click(await screen.findByRole("button", { name: "Recommend mapping" }));
  await screen.findByRole("region", { name: "TPDO1 draft" });
}

describe("PdoPage", () => {
  it("shows the device's PDOs in words and as the frame's byte layout", async () => {
    render();
    const tpdo = await screen.findByRole("region", { name: "TPDO1" });
    const card = within(tpdo);
    expect(card.getByText("0x181")).toBeTruthy();
    expect(card.getByText("every 5th SYNC")).toBeTruthy();
    expect(card.getByText("2.5 ms")).toBeTruthy(); // inhibit 25 × 100 µs
    expect(card.getByText("100 ms")).toBeTruthy();
    const frame = card.getByRole("list", { name: "TPDO1 frame" });
    const blocks = within(frame).getAllByRole("listitem");
    expect(blocks.map((b) => b.getAttribute("aria-label"))).toEqual([
      "Statusword (6041h:00, 16 bit)",
      "2FFFh:03 (2FFFh:03, 8 bit)", // unknown to the dictionary: raw
    ]);
    expect(blocks[0]?.style.gridColumn).toBe("1 / span 16");
    expect(blocks[1]?.style.gridColumn).toBe("17 / span 8");
    expect(card.getByText("24 of 64 bits · 3 bytes sent")).toBeTruthy();
    // PDOs neither valid nor mapped fold into one line
    expect(screen.queryByRole("region", { name: "RPDO2" })).toBeNull();
    expect(screen.getByText(/Not valid and nothing mapped: RPDO2/)).toBeTruthy();
  });

  it("drafts a mapping for the chosen modes, validates it and shows the bus load", async () => {
    const fetch = render({
      "GET /api/nodes/1/pdos/recommended": { pdos: RECOMMENDED },
      "POST /api/nodes/1/pdos/validate": {
        ok: false,
        problems: [
          {
            kind: "tpdo",
            number: 1,
            message: "Every SYNC at 1 ms loads the bus too much",
            index: 0x6064,
            subindex: 0,
          },
          { kind: "rpdo", number: 2, message: "RPDO2 uses a COB-ID another node sends" },
        ],
        bus_load: LOAD,
      },
    });
    await userEvent.click(await screen.findByLabelText("Profile velocity (PV)"));
    await recommendPp();
    expect(fetch.urls.some((u) => u.endsWith("/recommended?modes=pp%2Cpv"))).toBe(true);
    const tpdo = within(screen.getByRole("region", { name: "TPDO1 draft" }));
    expect(tpdo.getByText("draft: changed")).toBeTruthy();
    expect(tpdo.getByRole("list", { name: "TPDO1 frame on the device" })).toBeTruthy();
    expect(
      within(tpdo.getByRole("list", { name: "TPDO1 frame" })).getAllByRole("listitem"),
    ).toHaveLength(2);
    expect(screen.getByText(/2 PDOs differ from the device: RPDO1, TPDO1/)).toBeTruthy();

    await userEvent.click(screen.getByRole("button", { name: "Validate" }));
    expect(await screen.findByText("2 problems")).toBeTruthy();
    expect(tpdo.getByText("Every SYNC at 1 ms loads the bus too much")).toBeTruthy();
    // the object a problem names is outlined in the frame
    const flagged = tpdo.getByRole("listitem", { name: /^Position actual value/ });
    expect(flagged.className).toContain("flagged");
    // an unused PDO that a problem names comes out of the folded line
    const rpdo2 = within(screen.getByRole("region", { name: "RPDO2 draft" }));
    expect(rpdo2.getByText("RPDO2 uses a COB-ID another node sends")).toBeTruthy();
    expect(
      JSON.parse(fetch.calls.find((c) => c.path.endsWith("/validate"))?.body ?? "{}"),
    ).toHaveProperty("pdos.length", 4);
    const load = within(screen.getByTestId("bus-load"));
    expect(load.getByText("Bus load with the draft")).toBeTruthy();
    expect(load.getByRole("meter", { name: "Total bus load" }).getAttribute("aria-valuenow")).toBe(
      "80",
    );
    expect(load.getByRole("alert").textContent).toContain("above 70 %");
    expect(load.getByText("every SYNC at 1000 µs")).toBeTruthy();
    const threshold = load.getByLabelText("Warn above");
    await userEvent.clear(threshold);
    await userEvent.type(threshold, "90");
    expect(load.queryByRole("alert")).toBeNull();
  });

  it("applies after saying what changes, then shows the read-back", async () => {
    const readBack = DEVICE.map(
      (p) => RECOMMENDED.find((r) => r.kind === p.kind && r.number === p.number) ?? p,
    );
    const fetch = render({
      "GET /api/nodes/1/pdos/recommended": { pdos: RECOMMENDED },
      "PUT /api/nodes/1/pdos": readBack,
    });
    await recommendPp();
    await userEvent.click(screen.getByRole("button", { name: "Apply…" }));
    const dialog = within(screen.getByRole("dialog"));
    expect(dialog.getByText(/mapping → Controlword, Target position/)).toBeTruthy();
    expect(dialog.getByText(/transmission 5 → 1 \(every SYNC\)/)).toBeTruthy();
    await userEvent.click(dialog.getByRole("button", { name: "Apply" }));
    expect(await screen.findByText(/Read back from the device: 4 PDOs, 2 valid/)).toBeTruthy();
    expect(screen.queryByRole("region", { name: "Draft" })).toBeNull();
    expect(screen.getByRole("region", { name: "TPDO1" })).toBeTruthy();
    const put = fetch.calls.find((c) => c.method === "PUT");
    expect((JSON.parse(put?.body ?? "{}") as { pdos: unknown[] }).pdos).toHaveLength(4);
  });

  it("shows the failed step, the abort code and whether the device was restored", async () => {
    render({
      "GET /api/nodes/1/pdos/recommended": { pdos: RECOMMENDED },
      "PUT /api/nodes/1/pdos": json(
        {
          error: "pdo_apply_failed",
          step: "write 1A00h:02 (TPDO1 mapping entry 2)",
          abort_code: "0x06040041",
          message: "Object cannot be mapped to the PDO",
          restored: true,
        },
        409,
      ),
    });
    await recommendPp();
    await userEvent.click(screen.getByRole("button", { name: "Apply…" }));
    await userEvent.click(
      within(screen.getByRole("dialog")).getByRole("button", { name: "Apply" }),
    );
    const result = within(await screen.findByRole("alert", { name: "Apply result" }));
    expect(result.getByText("write 1A00h:02 (TPDO1 mapping entry 2)")).toBeTruthy();
    expect(result.getByText(/0x06040041/)).toBeTruthy();
    expect(result.getByText(/Object cannot be mapped to the PDO/)).toBeTruthy();
    expect(result.getByText(/Restored: the previous PDO settings were written back/)).toBeTruthy();
  });

  it("lists problems of a refused apply next to their PDO", async () => {
    render({
      "GET /api/nodes/1/pdos/recommended": { pdos: RECOMMENDED },
      "PUT /api/nodes/1/pdos": json(
        {
          error: "invalid_value",
          message: "node 1: RPDO1 maps 72 bits; nothing was written",
          problems: [{ kind: "rpdo", number: 1, message: "RPDO1 maps 72 bits, more than 64" }],
        },
        422,
      ),
    });
    await recommendPp();
    await userEvent.click(screen.getByRole("button", { name: "Apply…" }));
    await userEvent.click(
      within(screen.getByRole("dialog")).getByRole("button", { name: "Apply" }),
    );
    expect(await screen.findByText("Not applied")).toBeTruthy();
    const rpdo = within(screen.getByRole("region", { name: "RPDO1 draft" }));
    expect(rpdo.getByText("RPDO1 maps 72 bits, more than 64")).toBeTruthy();
  });
});
