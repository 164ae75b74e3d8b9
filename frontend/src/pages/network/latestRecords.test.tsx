import { screen, within } from "@testing-library/react";
import { afterEach, describe, expect, it, vi } from "vitest";

import type { NodeInfo } from "../../api/types";
import { stubFetch } from "../../test/fetchStub";
import { record } from "../../test/fixtures/commission";
import { renderPage } from "../../test/render";
import { latestByNode } from "./latestRecords";
import { NetworkPage } from "./NetworkPage";

afterEach(() => {
  vi.unstubAllGlobals();
});

const node = (id: number, name: string): NodeInfo => ({
  node: id,
  name,
  vendor_id: 0x26c,
  product_code: 0xc5,
  profile: "cia402",
  profile_label: "CiA 402",
  nmt_state: "pre-operational",
  online: true,
  heartbeat_age_ms: 40,
  od_source: "profile",
  od_filename: "cia402/drive.eds",
  od_warnings: 0,
});

describe("latest commissioning records", () => {
  it("keeps each node's newest record of a newest-first list", () => {
    const latest = latestByNode([
      record({ id: 3, node: 3, status: "failed" }),
      record({ id: 2, node: 1, status: "done" }),
      record({ id: 1, node: 3, status: "done" }),
    ]);
    expect(latest.get(3)).toEqual({ id: 3, status: "failed", title: "Axis X" });
    expect(latest.get(1)?.id).toBe(2);
    expect(latest.get(2)).toBeUndefined();
  });

  it("shows them in the Network page's node list, loaded once", async () => {
    const stub = stubFetch({
      "GET /api/bus/interfaces": [],
      "GET /api/nodes/1/heartbeat": { producer_ms: 0 },
      "GET /api/nodes/3/heartbeat": { producer_ms: 0 },
      "GET /api/events": { events: [], next: null },
      "GET /api/commissioning": [record({ id: 4, node: 3, status: "failed" })],
    });
    const { store } = renderPage(<NetworkPage />);
    store.setInfos([node(1, "DVS_CANOPEN"), node(3, "C5-E-SIM")]);

    const chip = await screen.findByRole("link", { name: "Commissioning of node 3: record #4" });
    expect(chip.getAttribute("href")).toBe("/nodes/3/commission");
    expect(within(chip).getByText("Failed")).toBeTruthy();
    const none = screen.getByRole("link", { name: "Commission node 1: no record yet" });
    expect(none.textContent).toBe("—");
    expect(stub.urls.filter((u) => u.includes("/api/commissioning"))).toHaveLength(1);
  });
});
