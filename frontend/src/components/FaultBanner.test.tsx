import { screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { Route, Routes } from "react-router";
import { afterEach, describe, expect, it, vi } from "vitest";

import { mdiAlarm4 } from "../pages/faults/fixtures";
import { stubFetch } from "../test/fetchStub";
import { renderPage } from "../test/render";
import { FaultBanner } from "./FaultBanner";

afterEach(() => {
  vi.unstubAllGlobals();
});

describe("FaultBanner", () => {
  it("names the node and fault, and leads to its Faults tab", async () => {
    stubFetch({ "GET /api/faults/active": { faults: [mdiAlarm4()] } });
    renderPage(
      <>
        <FaultBanner />
        <Routes>
          <Route path="/" element={<p>network</p>} />
          <Route path="/nodes/:node/faults" element={<p>faults tab</p>} />
        </Routes>
      </>,
    );
    const banner = await screen.findByRole("alert", { name: "Nodes in fault" });
    expect(banner.textContent).toContain("Node 1 in fault: alarm 4 位置超差 Following error");
    await userEvent.click(screen.getByRole("link", { name: "Open node 1 faults" }));
    expect(await screen.findByText("faults tab")).toBeTruthy();
  });

  it("shows nothing without faults or when the poll fails", async () => {
    const stub = stubFetch({ "GET /api/faults/active": { faults: [] } });
    const { container } = renderPage(<FaultBanner />);
    await vi.waitFor(() => expect(stub.calls.length).toBeGreaterThan(0));
    expect(container.textContent).toBe("");
    vi.unstubAllGlobals();
    stubFetch({});
    const again = renderPage(<FaultBanner />);
    await new Promise((resolve) => setTimeout(resolve, 20));
    expect(again.container.textContent).toBe("");
  });
});
