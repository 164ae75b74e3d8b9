import { screen, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { json, stubFetch } from "../../test/fetchStub";
import { renderPage } from "../../test/render";
import { DEVICE_TYPE, TREE, UPLOAD_ALL } from "./fixtures";
import { OdPage } from "./OdPage";

afterEach(() => {
  vi.unstubAllGlobals();
});

describe("OdPage", () => {
  it("lists the dictionary's objects and filters them by address", async () => {
    stubFetch({ "GET /api/nodes/3/od": TREE });
    renderPage(<OdPage node={3} />, "/nodes/3/od");
    const tree = await screen.findByRole("list", { name: "Object dictionary" });
    expect(within(tree).getByText("Device type")).toBeTruthy();
    expect(within(tree).getByText("Modes of operation")).toBeTruthy();
    expect(screen.getByText("5 of 5")).toBeTruthy();

    await userEvent.type(screen.getByRole("searchbox", { name: "Search objects" }), "1018:2");
    expect(await screen.findByText("Product code")).toBeTruthy();
    expect(within(tree).queryByText("Device type")).toBeNull();
    expect(screen.getByText("1 of 5")).toBeTruthy();
  });

  it("reads an entry and shows value, raw bytes and text", async () => {
    stubFetch({
      "GET /api/nodes/3/od": TREE,
      "GET /api/nodes/3/sdo/1000/00": DEVICE_TYPE,
    });
    renderPage(<OdPage node={3} />, "/nodes/3/od");
    await userEvent.click(await screen.findByRole("button", { name: /^1000\s*Device type$/ }));
    expect(screen.getByText("read only")).toBeTruthy();
    expect(screen.queryByRole("button", { name: "Write" })).toBeNull(); // read-only: no write
    await userEvent.click(screen.getByRole("button", { name: "Read" }));
    expect((await screen.findByTestId("sdo-value")).textContent).toBe("131474");
    expect(screen.getByText("92 01 02 00")).toBeTruthy();
    expect(screen.getAllByText("0x00020192 (131474)")).toHaveLength(2); // details and tree value
  });

  it("checks a write against the type and shows an SDO abort in place", async () => {
    const fetch = stubFetch({
      "GET /api/nodes/3/od": TREE,
      "PUT /api/nodes/3/sdo/6060/00": json(
        {
          error: "sdo_abort",
          message: "Invalid value for parameter (download only)",
          abort_code: "0x06090030",
        },
        409,
      ),
    });
    renderPage(<OdPage node={3} />, "/nodes/3/od");
    await userEvent.click(
      await screen.findByRole("button", { name: /^6060\s*Modes of operation$/ }),
    );
    const input = screen.getByLabelText("New value");
    await userEvent.type(input, "200");
    await userEvent.click(screen.getByRole("button", { name: "Write" }));
    expect(screen.getByRole("alert").textContent).toContain("out of range for INTEGER8");
    expect(fetch.calls.some((c) => c.method === "PUT")).toBe(false);

    await userEvent.clear(input);
    await userEvent.type(input, "-0x2");
    await userEvent.click(screen.getByRole("button", { name: "Write" }));
    expect((await screen.findByRole("alert")).textContent).toBe(
      "0x06090030 — Invalid value for parameter (download only)",
    );
    expect(JSON.parse(fetch.calls.find((c) => c.method === "PUT")?.body ?? "{}")).toEqual({
      value: -2,
      confirm: false,
    });
  });

  it("sends a write the server asks about again only when confirmed", async () => {
    const fetch = stubFetch({
      "GET /api/nodes/3/od": TREE,
      "PUT /api/nodes/3/sdo/6060/00": async (request: Request) => {
        const body = (await request.json()) as { confirm: boolean };
        return body.confirm
          ? { node: 3, index: 0x6060, subindex: 0, value: 1, raw_hex: "01", text: "1" }
          : json({ error: "confirmation_required", message: "below 10 ms needs confirm" }, 428);
      },
    });
    renderPage(<OdPage node={3} />, "/nodes/3/od");
    await userEvent.click(
      await screen.findByRole("button", { name: /^6060\s*Modes of operation$/ }),
    );
    await userEvent.type(screen.getByLabelText("New value"), "1");
    await userEvent.click(screen.getByRole("button", { name: "Write" }));
    await userEvent.click(await screen.findByRole("button", { name: "Write anyway" }));
    const puts = fetch.calls
      .filter((c) => c.method === "PUT")
      .map((c) => JSON.parse(c.body) as unknown);
    expect(puts).toEqual([
      { value: 1, confirm: false },
      { value: 1, confirm: true },
    ]);
  });

  it("fills the values column from an upload-all job, polling only for new results", async () => {
    const fetch = stubFetch({
      "GET /api/nodes/3/od": TREE,
      ...UPLOAD_ALL,
    });
    renderPage(<OdPage node={3} />, "/nodes/3/od");
    await userEvent.click(await screen.findByRole("button", { name: "Upload all" }));
    expect(await screen.findByText("0x00000001 (1)")).toBeTruthy();
    expect(await screen.findByText(/2\/2 · done/, {}, { timeout: 3000 })).toBeTruthy();
    expect(screen.getByText(/1 not readable/)).toBeTruthy();
    expect(
      screen.getByText("0x06020000 Object does not exist in the object dictionary"),
    ).toBeTruthy();
    const poll = fetch.calls.find((c) => c.path === "/api/jobs/j1");
    expect(poll).toBeTruthy();
    expect(fetch.urls.some((u) => u.endsWith("/api/jobs/j1?since=1"))).toBe(true);
  });
});
