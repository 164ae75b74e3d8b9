import { screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { stubFetch } from "../test/fetchStub";
import { renderPage } from "../test/render";
import { QuickStopAllButton, quickStopSummary } from "./QuickStopButton";

afterEach(() => {
  vi.unstubAllGlobals();
});

describe("quick stop all", () => {
  it("stops every drive in one click and says which", async () => {
    const fetch = stubFetch({
      "POST /api/quick-stop": { stopped: [1, 3], failed: { "2": "node 2 does not answer" } },
    });
    renderPage(<QuickStopAllButton />);
    await userEvent.click(screen.getByRole("button", { name: "■ Quick stop all" }));
    expect(
      await screen.findByText("Stopped nodes 1, 3; not reached: node 2 (node 2 does not answer)"),
    ).toBeTruthy();
    expect(fetch.calls.map((c) => `${c.method} ${c.path}`)).toEqual(["POST /api/quick-stop"]);
  });

  it.each([
    [{ stopped: [1], failed: {} }, "Stopped node 1"],
    [{ stopped: [], failed: {} }, "No drive to stop"],
  ])("summarises %j", (result, text) => {
    expect(quickStopSummary(result)).toBe(text);
  });
});
