import { screen, waitFor } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { LiveStore } from "../../live/store";
import { stubFetch } from "../../test/fetchStub";
import { renderPage } from "../../test/render";
import { INFO, PLAN, TREE, VIEWER, capture } from "./fixtures";
import { ScopePage } from "./ScopePage";

afterEach(() => {
  vi.unstubAllGlobals();
  window.sessionStorage.clear();
});

describe("ScopePage arming", () => {
  it("says the capture is not armed yet until the server says armed", async () => {
    const trigger = {
      kind: "level" as const,
      node: 1,
      index: 0x6064,
      subindex: 0,
      level: 1000,
      edge: "rising" as const,
      bit: null,
      state: null,
      pre_s: 0,
      mode: "single" as const,
      keep: 10,
    };
    let polled = 0;
    stubFetch({
      "GET /api/scope/viewer": VIEWER,
      "GET /api/scope/captures": [],
      "GET /api/nodes/1/od": TREE,
      "POST /api/scope/plan": PLAN,
      "POST /api/scope/captures": capture({ state: "arming", samples: 0, trigger }),
      "GET /api/scope/captures/7": () => {
        polled += 1;
        return capture({ state: polled < 3 ? "arming" : "armed", samples: 0, trigger });
      },
    });
    const store = new LiveStore();
    store.upsertInfo(INFO);
    renderPage(<ScopePage />, "/scope", store);

    await userEvent.click(await screen.findByRole("button", { name: "Position 6064h" }));
    const start = screen.getByRole("button", { name: "● Start capture" });
    await waitFor(() => expect(start).toHaveProperty("disabled", false));
    await userEvent.click(start);

    const state = await screen.findByTestId("capture-state");
    expect(state.textContent).toBe("Arming… (not armed yet)");
    expect(screen.getByRole("button", { name: "■ Stop" })).toBeTruthy(); // it can be stopped
    expect(start).toHaveProperty("disabled", true);
    await waitFor(
      () =>
        expect(screen.getByTestId("capture-state").textContent).toBe(
          "Armed: waiting for the trigger",
        ),
      { timeout: 3000 },
    );
  });
});
