import { screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { LiveStore } from "../../live/store";
import { stubFetch } from "../../test/fetchStub";
import { CONTROLLER, DRIVE, METHODS } from "../../test/fixtures/drive";
import { renderPage, sessionAs } from "../../test/render";
import { DrivePage } from "./DrivePage";

afterEach(() => {
  vi.unstubAllGlobals();
});

const ROUTES = {
  "GET /api/nodes/1/drive": DRIVE,
  "GET /api/nodes/1/drive/controller": CONTROLLER,
  "GET /api/nodes/1/drive/homing-methods": METHODS,
  "POST /api/nodes/1/drive/quick-stop": { ...DRIVE, state: "quick_stop_active" },
};

describe("the Drive page by role", () => {
  it("a viewer sees Enable disabled with the reason, and may still quick stop", async () => {
    const fetch = stubFetch(ROUTES);
    renderPage(<DrivePage node={1} />, "/nodes/1/drive", new LiveStore(), sessionAs("viewer"));

    const enable = await screen.findByRole("button", { name: "Enable" });
    expect(enable).toHaveProperty("disabled", true);
    expect(enable.getAttribute("title")).toBe(
      "Viewer role: read only — log in as an operator or engineer to enable the drive",
    );
    const disable = screen.getByRole("button", { name: "Disable" });
    expect(disable).toHaveProperty("disabled", true);
    expect(screen.getByRole("button", { name: "Take control" })).toHaveProperty("disabled", true);

    const stop = screen.getByRole("button", { name: "Quick stop node 1" });
    expect(stop).toHaveProperty("disabled", false);
    await userEvent.click(stop);
    expect(fetch.calls.some((c) => c.path === "/api/nodes/1/drive/quick-stop")).toBe(true);
  });

  it("an operator may enable the drive", async () => {
    stubFetch(ROUTES);
    renderPage(<DrivePage node={1} />, "/nodes/1/drive", new LiveStore(), sessionAs("operator"));
    const enable = await screen.findByRole("button", { name: "Enable" });
    expect(enable).toHaveProperty("disabled", false);
    expect(enable.getAttribute("title")).toContain("Shutdown, switch on, enable operation");
  });
});
