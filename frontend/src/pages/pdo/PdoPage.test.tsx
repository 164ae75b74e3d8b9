import { screen, waitFor, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { LiveStore } from "../../live/store";
import { json, stubFetch, type Handler } from "../../test/fetchStub";
import { renderPage } from "../../test/render";
import { CIA402_RULES, DEVICE, INFO, loadFor, RECOMMENDED, RULES, TREE } from "./fixtures";
import { PdoPage } from "./PdoPage";

afterEach(() => {
  vi.unstubAllGlobals();
});

const BASE = {
  "GET /api/nodes/1/pdos": DEVICE,
  "GET /api/nodes/1/od": TREE,
  "GET /api/bus-load": (request: Request) => loadFor(request, 12),
  "GET /api/sync": { producing: false, period_us: null },
  "GET /api/nodes/1/pdos/rules": RULES,
};

function render(
  routes: Record<string, Handler | object> = {},
  info = INFO,
): ReturnType<typeof stubFetch> {
  const fetch = stubFetch({ ...BASE, ...routes });
  const store = new LiveStore();
  store.upsertInfo(info);
  renderPage(<PdoPage node={1} />, "/nodes/1/pdos", store);
  return fetch;
}

/** The text of what an element's aria-describedby names. */
function description(element: HTMLElement): string {
  const ids = element.getAttribute("aria-describedby")?.split(/\s+/) ?? [];
  return ids.map((id) => document.getElementById(id)?.textContent ?? "").join(" ");
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
      "POST /api/nodes/1/pdos/validate": (request: Request) => ({
        ok: false,
        problems: [
          {
            kind: "tpdo",
            number: 1,
            message: "TPDO1: 6064h:00 Position actual value is not PDO-mappable",
            index: 0x6064,
            subindex: 0,
          },
          {
            kind: "tpdo",
            number: 1,
            message: "TPDO1 is synchronous (every SYNC) but nothing produces SYNC",
            index: 0x1800,
            subindex: 2,
          },
          {
            kind: "rpdo",
            number: 2,
            message: "RPDO2 uses a COB-ID another node sends",
            index: null,
            subindex: null,
          },
        ],
        bus_load: loadFor(request),
      }),
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
    expect(await screen.findByText("3 problems")).toBeTruthy();
    // the object a problem names is outlined in the frame, the message written under it
    const flagged = tpdo.getByRole("listitem", { name: /^Position actual value/ });
    expect(flagged.className).toContain("flagged");
    expect(description(flagged)).toBe("TPDO1: 6064h:00 Position actual value is not PDO-mappable");
    const frame = within(tpdo.getByRole("list", { name: "TPDO1 frame" }));
    expect(frame.getByRole("listitem", { name: /^Statusword/ }).className).not.toContain("flagged");
    // a problem with a communication parameter marks its field
    const type = tpdo.getByLabelText("TPDO1 transmission type");
    expect(type.getAttribute("aria-invalid")).toBe("true");
    expect(description(type)).toMatch(/Transmission type: TPDO1 is synchronous/);
    expect(tpdo.queryByRole("list", { name: "TPDO1 problems" })).toBeNull();
    // an unused PDO that a problem names comes out of the folded line
    const rpdo2 = within(screen.getByRole("region", { name: "RPDO2 draft" }));
    expect(rpdo2.getByText("RPDO2 uses a COB-ID another node sends")).toBeTruthy();
    expect(
      JSON.parse(fetch.calls.find((c) => c.path.endsWith("/validate"))?.body ?? "{}"),
    ).toHaveProperty("pdos.length", 4);
    expect(fetch.urls.find((u) => u.includes("/validate"))).toMatch(
      /\/validate\?threshold=70&master_period_ms=10$/,
    );
    const load = within(screen.getByTestId("bus-load"));
    expect(load.getByText("Bus load with the draft")).toBeTruthy();
    expect(load.getByRole("meter", { name: "Total bus load" }).getAttribute("aria-valuenow")).toBe(
      "80",
    );
    expect(load.getByRole("alert").textContent).toContain("above 70 %");
    expect(load.getByText("every SYNC at 1000 µs")).toBeTruthy();
    // the notes stay folded
    const notes = load.getByText(/^1 note on how the load is estimated/).closest("details");
    expect(notes?.open).toBe(false);
    // the server compares against the threshold: a new one checks the draft again
    const threshold = load.getByLabelText("Warn above");
    await userEvent.clear(threshold);
    await userEvent.type(threshold, "90");
    await waitFor(() => expect(load.queryByRole("alert")).toBeNull());
    expect(fetch.urls.filter((u) => u.includes("/validate")).at(-1)).toMatch(/threshold=90&/);
  });

  it("passes the warning threshold and the master's cycle to the bus load", async () => {
    const fetch = render({ "GET /api/bus-load": (request: Request) => loadFor(request) });
    const loads = (): string[] => fetch.urls.filter((u) => u.includes("/api/bus-load"));
    const load = within(await screen.findByTestId("bus-load"));
    expect(load.getByText("Bus load now")).toBeTruthy();
    expect(load.getByRole("alert").textContent).toContain("above 70 %");
    expect(loads().at(-1)).toMatch(/\/api\/bus-load\?threshold=70&master_period_ms=10$/);
    const cycle = load.getByLabelText("Master cycle");
    await userEvent.clear(cycle);
    await userEvent.type(cycle, "4");
    await waitFor(() =>
      expect(loads().at(-1)).toMatch(/\/api\/bus-load\?threshold=70&master_period_ms=4$/),
    );
    // the field keeps its focus: the view stays while the load reloads
    expect(document.activeElement).toBe(cycle);
    const threshold = load.getByLabelText("Warn above");
    await userEvent.clear(threshold);
    await userEvent.type(threshold, "85");
    await waitFor(() => expect(load.queryByRole("alert")).toBeNull());
    expect(document.activeElement).toBe(threshold);
    expect(loads().at(-1)).toMatch(/threshold=85&master_period_ms=4$/);
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
    expect(dialog.getByText(/How node 1 takes the new mapping:/).parentElement?.textContent).toBe(
      `How node 1 takes the new mapping: ${RULES.procedure}. If a step fails, the previous settings are written back.`,
    );
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
          problems: [
            {
              kind: "rpdo",
              number: 1,
              message: "RPDO1 maps 72 bits, more than 64",
              index: 0x1600,
              subindex: 0,
            },
            {
              kind: "rpdo",
              number: 1,
              message: "RPDO1: 607Ah:00 Target position is read-only",
              index: 0x607a,
              subindex: 0,
            },
          ],
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
    expect(
      within(rpdo.getByRole("list", { name: "RPDO1 problems" })).getByText(
        /RPDO1 maps 72 bits, more than 64/,
      ),
    ).toBeTruthy();
    const target = rpdo.getByRole("listitem", { name: /^Target position/ });
    expect(target.className).toContain("flagged");
    expect(description(target)).toBe("RPDO1: 607Ah:00 Target position is read-only");
  });

  it("warns that a drive changing PDOs outside Operational stops its PDOs meanwhile", async () => {
    render(
      {
        "GET /api/nodes/1/pdos/rules": CIA402_RULES,
        "GET /api/nodes/1/pdos/recommended": { pdos: RECOMMENDED },
      },
      { ...INFO, nmt_state: "operational" },
    );
    await recommendPp();
    await userEvent.click(screen.getByRole("button", { name: "Apply…" }));
    const dialog = within(screen.getByRole("dialog"));
    expect(
      dialog.getByText(/How node 1 takes the new mapping:/).parentElement?.textContent,
    ).toContain("Pre-operational, then the MDi order");
    expect(dialog.getByText(/Node 1 is operational: it goes to pre-operational/)).toBeTruthy();
  });
});
