import { screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { stubFetch } from "../../test/fetchStub";
import { renderPage } from "../../test/render";
import { decoded, event, kept, notRecording } from "./fixtures";
import { LogsPage } from "./LogsPage";

afterEach(() => {
  vi.unstubAllGlobals();
});

describe("LogsPage", () => {
  it("decodes an uploaded log: summary first, totals, events paged, exports", async () => {
    const stub = stubFetch({
      "GET /api/recording": notRecording,
      "POST /api/logs/decode": decoded,
      "GET /api/logs/abc123/events": {
        events: Array.from({ length: 200 }, (_, i) => event(500 + i, "emcy", `late ${i}`)),
        next: null,
      },
    });
    renderPage(<LogsPage />, "/logs");
    const file = new File(["(1.0) can0 701#00\n"], "bus.log", { type: "text/plain" });
    await userEvent.upload(screen.getByLabelText("Choose CAN log…"), file);

    const summary = await screen.findByRole("list", { name: "Summary" });
    expect(within(summary).getAllByRole("listitem")[0]?.textContent).toContain("1,200 frames");
    expect(summary.textContent).toContain("alarm 4 位置超差 Following error");
    const totals = screen.getByLabelText("Log totals");
    expect(totals.textContent).toContain("Frames1,200");
    expect(totals.textContent).toContain("Bus loadpeak 3.1 %, mean 1.2 %");
    expect(await screen.findByText("Events 1–500 of 700")).toBeTruthy();
    expect(screen.getByRole("link", { name: "Parquet" }).getAttribute("href")).toBe(
      "/api/logs/abc123/export?format=parquet",
    );
    const post = stub.calls.find((c) => c.path === "/api/logs/decode");
    expect(post?.body).toContain('name="file"');
    expect(post?.body).not.toContain('name="dcf"');

    await userEvent.click(screen.getByRole("button", { name: "Next →" }));
    expect(await screen.findByText("Events 501–700 of 700")).toBeTruthy();
    expect(screen.getByText("late 0")).toBeTruthy();
    expect(stub.urls.some((u) => u.includes("/api/logs/abc123/events?since=500&limit=500"))).toBe(
      true,
    );
    expect(screen.getByRole<HTMLButtonElement>("button", { name: "Next →" }).disabled).toBe(true);
    await userEvent.click(screen.getByRole("button", { name: "← Previous" }));
    expect(await screen.findByText("Events 1–500 of 700")).toBeTruthy();
  });

  it("sends the DCF with the log when one is chosen", async () => {
    const stub = stubFetch({
      "GET /api/recording": notRecording,
      "POST /api/logs/decode": decoded,
    });
    renderPage(<LogsPage />, "/logs");
    await userEvent.upload(
      screen.getByLabelText("Choose DCF (optional)…"),
      new File(["[FileInfo]\n"], "node1.dcf"),
    );
    expect(screen.getByText("node1.dcf")).toBeTruthy();
    await userEvent.upload(screen.getByLabelText("Choose CAN log…"), new File(["x"], "bus.log"));
    await screen.findByRole("list", { name: "Summary" });
    const post = stub.calls.find((c) => c.path === "/api/logs/decode");
    expect(post?.body).toContain('name="dcf"');
  });

  it("records the bus: start, see it count, stop and download", async () => {
    let active = false;
    const status = () => ({
      active,
      format: active ? "asc" : null,
      file: active ? "rec.asc" : null,
      since: active ? Date.now() / 1000 : null,
      frames: active ? 42 : 0,
      dropped: 0,
    });
    const saved: string[] = [];
    vi.spyOn(HTMLAnchorElement.prototype, "click").mockImplementation(function (
      this: HTMLAnchorElement,
    ) {
      saved.push(this.download);
    });
    URL.createObjectURL = vi.fn(() => "blob:x");
    URL.revokeObjectURL = vi.fn();
    const stub = stubFetch({
      "GET /api/recording": () => status(),
      "POST /api/recording": () => {
        active = true;
        return status();
      },
      "DELETE /api/recording": () => {
        active = false;
        return new Response("date Tue\nbase hex\n", {
          headers: {
            "Content-Type": "text/plain",
            "Content-Disposition": 'attachment; filename="rec.asc"',
          },
        });
      },
    });
    renderPage(<LogsPage />, "/logs");
    expect(await screen.findByText("Not recording")).toBeTruthy();
    await userEvent.selectOptions(screen.getByLabelText("Format"), "asc");
    await userEvent.click(screen.getByRole("button", { name: "Start recording" }));
    expect(await screen.findByText(/^Recording ASC: 42 frames/)).toBeTruthy();
    expect(JSON.parse(stub.calls.find((c) => c.method === "POST")?.body ?? "{}")).toEqual({
      format: "asc",
    });

    await userEvent.click(screen.getByRole("button", { name: "Stop and download" }));
    expect(await screen.findByText("rec.asc")).toBeTruthy();
    expect(saved).toEqual(["rec.asc"]);
    expect(await screen.findByText("Not recording")).toBeTruthy();
  });

  it("lists the decoded logs kept, opens one again and deletes one", async () => {
    let logs = kept;
    const stub = stubFetch({
      "GET /api/recording": notRecording,
      "GET /api/logs": () => logs,
      "GET /api/logs/abc123": decoded,
      "GET /api/logs/abc123/events": { events: [], next: null },
      "DELETE /api/logs/def456": () => {
        logs = logs.slice(0, 1);
        return new Response(null, { status: 204 });
      },
    });
    renderPage(<LogsPage />, "/logs");
    const table = await screen.findByRole("table", { name: "Decoded logs" });
    expect(
      within(table)
        .getAllByRole("row")
        .map((r) => r.textContent),
    ).toEqual([
      "LogDecodedSizeOpen · delete",
      expect.stringContaining("bus.log") as string,
      expect.stringContaining("old.blf") as string,
    ]);
    expect(table.textContent).toContain("3.0 MiB");
    const [, newest, oldest] = within(table).getAllByRole("row");
    if (!newest || !oldest) throw new Error("two logs listed");
    await userEvent.click(within(newest).getByRole("button", { name: "Open" }));
    expect(await screen.findByRole("list", { name: "Summary" })).toBeTruthy();
    await userEvent.click(within(oldest).getByRole("button", { name: "Delete" }));
    await userEvent.click(screen.getByRole("button", { name: "Delete old.blf" }));
    await screen.findByText("1 kept");
    expect(stub.calls.some((c) => c.method === "DELETE" && c.path === "/api/logs/def456")).toBe(
      true,
    );
    expect(screen.queryByText("old.blf")).toBeNull();
  });
});
