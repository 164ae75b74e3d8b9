import { screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { stubFetch } from "../../test/fetchStub";
import { renderPage } from "../../test/render";
import { Timeline } from "./Timeline";
import type { TimelineEvent } from "./types";

afterEach(() => {
  vi.unstubAllGlobals();
});

const ev = (id: number, kind = "nmt", node: number | null = 1): TimelineEvent => ({
  id,
  time: 1_764_000_000 + id,
  kind,
  node,
  message: `message ${id}`,
  data: {},
});

describe("Timeline", () => {
  it("shows the newest events, filters by node and kind, and pages back", async () => {
    const stub = stubFetch({
      "GET /api/events": (request: Request) => {
        const query = new URL(request.url).searchParams;
        if (query.get("before") === "9") return { events: [ev(8), ev(7)], next: null };
        if (query.get("since")) return { events: [], next: Number(query.get("since")) };
        if (query.get("kind") === "emcy") return { events: [ev(5, "emcy", 2)], next: null };
        return { events: [ev(10), ev(9)], next: 9 };
      },
    });
    const { store } = renderPage(<Timeline />);
    store.setInfos([]);
    expect(await screen.findByText("message 10")).toBeTruthy();
    const rows = screen.getAllByRole("row").slice(1);
    expect(rows.map((r) => r.textContent)).toEqual([
      expect.stringContaining("message 10"),
      expect.stringContaining("message 9"),
    ]);

    await userEvent.click(screen.getByRole("button", { name: "Older…" }));
    expect(await screen.findByText("message 7")).toBeTruthy();
    expect(screen.queryByRole("button", { name: "Older…" })).toBeNull();

    await userEvent.selectOptions(screen.getByLabelText("Kind"), "emcy");
    expect(await screen.findByText("message 5")).toBeTruthy();
    expect(screen.queryByText("message 10")).toBeNull();
    expect(stub.urls.some((u) => u.includes("kind=emcy"))).toBe(true);
  });
});
