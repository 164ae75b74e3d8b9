import { act, screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import type { TimelineEvent } from "../../api/timeline";
import { stubFetch } from "../../test/fetchStub";
import { renderPage } from "../../test/render";
import { Timeline } from "./Timeline";

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

  it("appends matching events from the socket and catches up after a gap or a reconnect", async () => {
    const stub = stubFetch({
      "GET /api/events": (request: Request) => {
        const query = new URL(request.url).searchParams;
        const since = query.get("since");
        if (query.get("kind") === "emcy") return { events: [], next: since ? Number(since) : null };
        if (since === "11") return { events: [ev(12), ev(13)], next: 13 };
        if (since === "14") return { events: [ev(15)], next: 15 };
        if (since) return { events: [], next: Number(since) };
        return { events: [ev(10), ev(9)], next: 9 };
      },
    });
    const { store } = renderPage(<Timeline />);
    expect(await screen.findByText("message 10")).toBeTruthy();
    // the page's effects after the first page ran (it takes the socket's events from then on;
    // one that comes earlier is fetched by a catch-up, which this stub does not model)
    await act(async () => {});
    const shown = (): string[] =>
      screen
        .getAllByRole("row")
        .slice(1)
        .map((r) => /message (\d+)/.exec(r.textContent)?.[1] ?? "");
    const push = (event: TimelineEvent): void =>
      act(() => store.apply({ type: "timeline", event }));

    push(ev(11));
    push(ev(11)); // twice: listed once
    expect(shown()).toEqual(["11", "10", "9"]);
    expect(stub.urls.filter((u) => u.includes("since="))).toEqual([]);

    push(ev(14)); // 12 and 13 were missed
    expect(await screen.findByText("message 12")).toBeTruthy();
    expect(shown()).toEqual(["14", "13", "12", "11", "10", "9"]);
    expect(stub.urls.some((u) => u.includes("since=11"))).toBe(true);

    // a reconnect fetches what the socket missed while down
    act(() => store.setLink({ state: "open", attempt: 0, retryAt: null }));
    expect(await screen.findByText("message 15")).toBeTruthy();
    expect(stub.urls.some((u) => u.includes("since=14"))).toBe(true);

    // a filtered list takes only the events that match
    await userEvent.selectOptions(screen.getByLabelText("Kind"), "emcy");
    await vi.waitFor(() => expect(screen.queryByText("message 10")).toBeNull());
    push(ev(16, "emcy", 2));
    push(ev(17, "nmt", 2));
    expect(await screen.findByText("message 16")).toBeTruthy();
    expect(screen.queryByText("message 17")).toBeNull();
  });

  it("catches up after the first page when the socket opened while it was on its way", async () => {
    // what was published between the first page's read and the socket's opening reaches the
    // page neither way: the list fetches it once the first page is in
    let answerFirst: (page: object) => void = () => undefined;
    const stub = stubFetch({
      "GET /api/events": (request: Request) => {
        const since = new URL(request.url).searchParams.get("since");
        if (since === "10") return { events: [ev(11)], next: 11 };
        if (since) return { events: [], next: Number(since) };
        return new Promise((resolve) => (answerFirst = resolve));
      },
    });
    const { store } = renderPage(<Timeline />);
    await vi.waitFor(() => expect(stub.urls).toHaveLength(1));
    act(() => store.setLink({ state: "open", attempt: 0, retryAt: null }));
    act(() => answerFirst({ events: [ev(10)], next: null }));
    expect(await screen.findByText("message 11")).toBeTruthy();
    expect(stub.urls.some((u) => u.includes("since=10"))).toBe(true);
  });
});
