import { act, screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { Route, Routes } from "react-router";
import { afterEach, describe, expect, it, vi } from "vitest";

import { stubFetch } from "../test/fetchStub";
import { mdiAlarm4 } from "../test/fixtures/faults";
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

  it("follows the socket's fault messages and reads REST again on a reconnect", async () => {
    let active = [mdiAlarm4()];
    const stub = stubFetch({ "GET /api/faults/active": () => ({ faults: active }) });
    const { store } = renderPage(<FaultBanner />);
    const banner = await screen.findByRole("alert", { name: "Nodes in fault" });
    expect(banner.textContent).toContain("Node 1 in fault");

    act(() => store.apply({ type: "fault", node: 2, fault: mdiAlarm4({ node: 2 }) }));
    expect(screen.getByRole("link", { name: "Open node 2 faults" })).toBeTruthy();
    act(() => store.apply({ type: "fault", node: 1, fault: null }));
    expect(screen.queryByRole("link", { name: "Open node 1 faults" })).toBeNull();
    act(() => store.apply({ type: "fault", node: 2, fault: null }));
    expect(screen.queryByRole("alert")).toBeNull();

    // no polling: one read on mount …
    await new Promise((resolve) => setTimeout(resolve, 50));
    expect(stub.calls).toHaveLength(1);
    // … and one when the socket (re)connects, for what it missed while down
    active = [mdiAlarm4({ node: 3 })];
    act(() => store.setLink({ state: "open", attempt: 0, retryAt: null }));
    expect(await screen.findByRole("link", { name: "Open node 3 faults" })).toBeTruthy();
    expect(stub.calls).toHaveLength(2);
  });
});
