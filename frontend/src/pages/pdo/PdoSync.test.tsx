import { screen, waitFor, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { LiveStore } from "../../live/store";
import { stubFetch, type Handler } from "../../test/fetchStub";
import { renderPage } from "../../test/render";
import { DEVICE, INFO, loadFor, RECOMMENDED, RULES, TREE } from "./fixtures";
import { PdoPage } from "./PdoPage";
import type { Validation } from "./types";

afterEach(() => {
  vi.unstubAllGlobals();
});

const QUIET = {
  producing: false,
  period_us: null,
  heard: false,
  heard_frames: 0,
  heard_period_us: null,
};
const WARNINGS = ["rpdo", "tpdo"].map((kind) => ({
  kind: kind as "rpdo" | "tpdo",
  number: 1,
  message: `${kind.toUpperCase()}1 is synchronous (every SYNC) but no SYNC is produced or heard`,
  index: kind === "rpdo" ? 0x1400 : 0x1800,
  subindex: 2,
}));

/** The server's answer: the SYNC warnings stand until the request names the controller. */
function validation(request: Request, body: { sync_source?: string | null }): Validation {
  const source = body.sync_source === "external" ? "external" : null;
  return {
    ok: source !== null,
    problems: [],
    warnings: WARNINGS,
    sync: { ...QUIET, source },
    bus_load: loadFor(request),
  };
}

function render(routes: Record<string, Handler | object>): ReturnType<typeof stubFetch> {
  const fetch = stubFetch({
    "GET /api/nodes/1/pdos": DEVICE,
    "GET /api/nodes/1/od": TREE,
    "GET /api/bus-load": (request: Request) => loadFor(request, 12),
    "GET /api/sync": { producing: false, period_us: null },
    "GET /api/nodes/1/pdos/rules": RULES,
    "GET /api/nodes/1/pdos/recommended": { pdos: RECOMMENDED },
    ...routes,
  });
  const store = new LiveStore();
  store.upsertInfo(INFO);
  renderPage(<PdoPage node={1} />, "/nodes/1/pdos", store);
  return fetch;
}

async function draftAndValidate(): Promise<void> {
  await userEvent.click(await screen.findByRole("button", { name: "Recommend mapping" }));
  await screen.findByRole("region", { name: "TPDO1 draft" });
  await userEvent.click(screen.getByRole("button", { name: "Validate" }));
}

describe("PdoPage SYNC", () => {
  it("warns of a synchronous mapping without SYNC and writes it for the machine's controller", async () => {
    const fetch = render({
      "POST /api/nodes/1/pdos/validate": async (request: Request) =>
        validation(request, (await request.clone().json()) as { sync_source?: string | null }),
      "PUT /api/nodes/1/pdos": DEVICE,
    });
    await draftAndValidate();
    expect(await screen.findByText("No SYNC on the bus")).toBeTruthy();
    const choice = within(screen.getByRole("group", { name: "SYNC for the synchronous PDOs" }));
    expect(choice.getByRole("alert").textContent).toMatch(
      /RPDO1, TPDO1 are synchronous but no SYNC is produced or heard on the bus/,
    );
    expect(choice.getByRole("button", { name: "Produce SYNC" })).toBeTruthy();

    await userEvent.click(choice.getByLabelText("SYNC comes from the machine's controller (PLC)"));
    expect(await screen.findByText("Checked: no problems")).toBeTruthy();
    const checks = fetch.calls.filter((c) => c.path.includes("/validate"));
    expect(JSON.parse(checks.at(-1)?.body ?? "{}")).toHaveProperty("sync_source", "external");
    expect(choice.getByRole("alert").textContent).toMatch(/It can be written/);

    await userEvent.click(screen.getByRole("button", { name: "Apply…" }));
    const dialog = within(screen.getByRole("dialog"));
    expect(dialog.getByText("SYNC comes from the machine's controller (PLC).")).toBeTruthy();
    await userEvent.click(dialog.getByRole("button", { name: "Apply" }));
    await waitFor(() => expect(fetch.calls.some((c) => c.method === "PUT")).toBe(true));
    const put = fetch.calls.find((c) => c.method === "PUT");
    expect(JSON.parse(put?.body ?? "{}")).toHaveProperty("sync_source", "external");
  });

  it("checks the draft again once SYNC is started from the warning", async () => {
    let producing = false;
    const fetch = render({
      "PUT /api/sync": () => {
        producing = true;
        return { producing: true, period_us: 10_000 };
      },
      "POST /api/nodes/1/pdos/validate": (request: Request) => ({
        ok: producing,
        problems: [],
        warnings: producing ? [] : WARNINGS,
        sync: { ...QUIET, producing, period_us: producing ? 10_000 : null, source: null },
        bus_load: loadFor(request),
      }),
    });
    await draftAndValidate();
    expect(await screen.findByText("No SYNC on the bus")).toBeTruthy();
    await userEvent.click(screen.getByRole("button", { name: "Produce SYNC" }));
    expect(await screen.findByText("Checked: no problems")).toBeTruthy();
    expect(fetch.calls.filter((c) => c.path.endsWith("/validate"))).toHaveLength(2);
    expect(screen.getByText("SYNC produced every 10 ms")).toBeTruthy();
    const choice = within(screen.getByRole("group", { name: "SYNC for the synchronous PDOs" }));
    expect(choice.queryByRole("alert")).toBeNull();
  });

  it("says so when SYNC from another producer is heard on the bus", async () => {
    render({
      "POST /api/nodes/1/pdos/validate": (request: Request) => ({
        ok: true,
        problems: [],
        warnings: [],
        sync: { ...QUIET, heard: true, heard_frames: 40, heard_period_us: 4000, source: null },
        bus_load: loadFor(request),
      }),
    });
    await draftAndValidate();
    expect(await screen.findByText("Checked: no problems")).toBeTruthy();
    expect(
      screen.getByText(
        "SYNC heard on the bus from another producer every 4 ms: RPDO1, TPDO1 get it.",
      ),
    ).toBeTruthy();
    expect(screen.queryByRole("group", { name: "SYNC for the synchronous PDOs" })).toBeNull();
  });
});
