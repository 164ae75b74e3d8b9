import { screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { LiveStore } from "../../live/store";
import { json, stubFetch } from "../../test/fetchStub";
import { renderPage, sessionAs } from "../../test/render";
import { AuditPage } from "./AuditPage";
import { PAGE_SIZE } from "./auditApi";
import { entry, FAILED, UNDO, WRITE } from "./fixtures";

afterEach(() => {
  vi.unstubAllGlobals();
});

describe("AuditPage", () => {
  it("lists who changed what: object, old → new, result with the abort code's meaning", async () => {
    stubFetch({ "GET /api/audit": [WRITE, FAILED] });
    renderPage(<AuditPage />, "/audit");

    const write = await screen.findByTestId("audit-12");
    expect(write.textContent).toContain("6081h:00");
    expect(write.textContent).toContain("1000 → 2000");
    expect(write.textContent).toContain("engineer");
    expect(write.textContent).toContain("127.0.0.1 · Firefox");
    const failed = screen.getByTestId("audit-11");
    expect(failed.className).toContain("audit-failed");
    expect(failed.textContent).toContain("0x06010002 — Attempt to write a read-only object");
    expect(within(failed).queryByRole("button", { name: "Undo entry 11" })).toBeNull();
  });

  it("undoes after naming the object and the value, then shows the new entry", async () => {
    let undone = false;
    const fetch = stubFetch({
      "GET /api/audit": () => (undone ? [UNDO, WRITE, FAILED] : [WRITE, FAILED]),
      "POST /api/audit/12/undo": () => {
        undone = true;
        return UNDO;
      },
    });
    renderPage(<AuditPage />, "/audit");
    await userEvent.click(await screen.findByRole("button", { name: "Undo entry 12" }));

    const dialog = screen.getByRole("dialog", { name: "Undo entry 12" });
    expect(dialog.textContent).toContain("Write 1000 back to 6081h:00 on node 1, replacing 2000?");
    await userEvent.click(within(dialog).getByRole("button", { name: "Write 1000 back" }));

    expect((await screen.findByTestId("audit-13")).textContent).toContain("undoes entry 12");
    expect(screen.getByTestId("audit-13").className).toContain("audit-fresh");
    expect(screen.getByRole("status").textContent).toContain("Undo logged as entry 13");
    expect(screen.queryByRole("dialog")).toBeNull();
    const post = fetch.calls.find((c) => c.method === "POST");
    expect(post?.path).toBe("/api/audit/12/undo");
    expect(post?.body).toBe('{"force":false}');
  });

  it("says why an undo was refused", async () => {
    stubFetch({
      "GET /api/audit": [WRITE],
      "POST /api/audit/12/undo": json(
        { error: "not_undoable", message: "entry 12 was undone already" },
        409,
      ),
    });
    renderPage(<AuditPage />, "/audit");
    await userEvent.click(await screen.findByRole("button", { name: "Undo entry 12" }));
    await userEvent.click(screen.getByRole("button", { name: "Write 1000 back" }));
    expect((await screen.findByRole("alert")).textContent).toBe("entry 12 was undone already");
  });

  it("offers Undo only to engineers", async () => {
    stubFetch({ "GET /api/audit": [WRITE] });
    renderPage(<AuditPage />, "/audit", new LiveStore(), sessionAs("operator"));
    const undo = await screen.findByRole("button", { name: "Undo entry 12" });
    expect(undo).toHaveProperty("disabled", true);
    expect(undo.getAttribute("title")).toContain("log in as an engineer to undo a change");
  });

  it("filters the list and the export alike, and pages to older entries", async () => {
    const page = Array.from({ length: PAGE_SIZE }, (_, i) => entry(500 - i));
    const fetch = stubFetch({
      "GET /api/audit": (request: Request) =>
        new URL(request.url).searchParams.has("before") ? [entry(7)] : page,
    });
    renderPage(<AuditPage />, "/audit");
    await screen.findByTestId("audit-500");

    await userEvent.type(screen.getByLabelText("Node"), "1");
    await userEvent.type(screen.getByLabelText("User"), "engineer");
    await userEvent.type(screen.getByLabelText("Action"), "sdo-write");
    // datetime-local: typed as the browser's local time
    const since = screen.getByLabelText("Since");
    await userEvent.type(since, "2025-06-15T14:30");
    await userEvent.click(screen.getByRole("button", { name: "Apply filters" }));

    const sinceS = Math.floor(new Date("2025-06-15T14:30").getTime() / 1000);
    const link = await screen.findByRole("link", { name: "Export CSV" });
    await vi.waitFor(() => {
      expect(link.getAttribute("href")).toBe(
        `/api/audit/export?format=csv&node=1&since=${sinceS}&user=engineer&action=sdo-write`,
      );
    });
    await vi.waitFor(() => {
      expect(fetch.urls.at(-1)).toContain(`since=${sinceS}`);
    });
    const query = new URL(fetch.urls.at(-1) ?? "").searchParams;
    expect(query.get("node")).toBe("1");
    expect(query.get("user")).toBe("engineer");
    expect(query.get("action")).toBe("sdo-write");

    await userEvent.click(await screen.findByRole("button", { name: "Load older" }));
    expect(await screen.findByTestId("audit-7")).toBeTruthy();
    const older = new URL(fetch.urls.at(-1) ?? "").searchParams;
    expect(older.get("before")).toBe("401");
    expect(older.get("node")).toBe("1");
    expect(screen.queryByRole("button", { name: "Load older" })).toBeNull();
  });
});
