// The Drive page says what the drive does: a faulted drive is reset only on purpose (two acts),
// a move stopped before its target is not "moving", the drive's own limits and where the travel
// ends are shown, and ServoDesk's travel limits are offered inside the limit switches.
import { screen, waitFor, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { LiveStore } from "../../live/store";
import { json, stubFetch, type Handler } from "../../test/fetchStub";
import { CONTROLLER, DRIVE, ENABLED, METHODS } from "../../test/fixtures/drive";
import { renderPage } from "../../test/render";
import { DrivePage } from "./DrivePage";
import { limitsInsideSwitches, moveText, travelRows } from "./motionWords";
import type { DriveState } from "./types";

afterEach(() => {
  vi.unstubAllGlobals();
});

const FAULT_MESSAGE =
  "fault 0x0004 Following error (MDi-S1-C CANopen manual §4.1) is active (statusword bit 3); " +
  "nothing resets it by itself: remove its cause, then send Fault reset";

const FAULTED: DriveState = {
  ...DRIVE,
  state: "fault",
  state_label: "Fault",
  statusword: 0x0218,
  fault: {
    code: 4,
    code_hex: "0x0004",
    name: "Following error",
    text: "Check the gains",
    source: "MDi-S1-C CANopen manual §4.1",
  },
};

const TRAVEL: DriveState = {
  ...ENABLED,
  limits: { ...ENABLED.limits, min_position_rev: null, max_position_rev: null },
  drive_limits: {
    max_velocity_rpm: 300,
    velocity_source: "2006h:08 PA-103 Maximum speed",
    max_torque_pct: 100,
    torque_source: "6072h Max torque",
  },
  travel: {
    switches: {
      min_rev: -5,
      max_rev: 5,
      source: "5FF1h / 5FF2h SIM limit switch positions",
      simulator: true,
      note: "the simulator's limit switches",
    },
    software_limit: null,
  },
};

function render(routes: Record<string, Handler | object>) {
  const fetch = stubFetch({
    "GET /api/nodes/1/drive": DRIVE,
    "GET /api/nodes/1/drive/controller": CONTROLLER,
    "GET /api/nodes/1/drive/homing-methods": METHODS,
    ...routes,
  });
  renderPage(<DrivePage node={1} />, "/nodes/1/drive", new LiveStore());
  return fetch;
}

describe("a faulted drive", () => {
  it("is reset only on purpose: fault reset, then enable, two requests", async () => {
    let current = FAULTED;
    const fetch = render({
      "GET /api/nodes/1/drive": () => current,
      "POST /api/nodes/1/drive/enable": () =>
        current.state === "fault"
          ? json(
              {
                error: "enable_blocked",
                message: `node 1 does not enable: ${FAULT_MESSAGE}`,
                reasons: [{ code: "fault", message: FAULT_MESSAGE }],
                state: FAULTED,
              },
              409,
            )
          : (current = ENABLED),
      "POST /api/nodes/1/drive/fault-reset": () =>
        (current = { ...DRIVE, last_transition: "fault reset (15)" }),
    });
    await userEvent.click(await screen.findByRole("button", { name: "Enable" }));
    const why = await screen.findByRole("alert", { name: "Why won't it enable?" });
    expect(within(why).getByText(FAULT_MESSAGE)).toBeTruthy();
    // the refused enable sent nothing else: no fault reset behind the user's back
    expect(fetch.calls.filter((c) => c.method === "POST").map((c) => c.path)).toEqual([
      "/api/nodes/1/drive/enable",
    ]);
    await userEvent.click(within(why).getByRole("button", { name: "Reset fault, then enable" }));
    await waitFor(() =>
      expect(screen.getByTestId("drive-state").textContent).toBe("Operation enabled"),
    );
    expect(fetch.calls.filter((c) => c.method === "POST").map((c) => c.path)).toEqual([
      "/api/nodes/1/drive/enable",
      "/api/nodes/1/drive/fault-reset",
      "/api/nodes/1/drive/enable",
    ]);
    expect(screen.queryByRole("alert", { name: "Why won't it enable?" })).toBeNull();
  });

  it("does not enable when the fault reset is refused", async () => {
    const fetch = render({
      "GET /api/nodes/1/drive": FAULTED,
      "POST /api/nodes/1/drive/enable": json(
        {
          error: "enable_blocked",
          message: "node 1 does not enable",
          reasons: [{ code: "fault", message: FAULT_MESSAGE }],
          state: FAULTED,
        },
        409,
      ),
      "POST /api/nodes/1/drive/fault-reset": json(
        {
          error: "enable_blocked",
          message: "node 1 does not reset",
          reasons: [{ code: "fault", message: FAULT_MESSAGE }],
          state: FAULTED,
        },
        409,
      ),
    });
    await userEvent.click(await screen.findByRole("button", { name: "Enable" }));
    const why = await screen.findByRole("alert", { name: "Why won't it enable?" });
    await userEvent.click(within(why).getByRole("button", { name: "Reset fault, then enable" }));
    expect(
      await screen.findByRole("alert", { name: "Why didn't Fault reset happen?" }),
    ).toBeTruthy();
    expect(fetch.calls.filter((c) => c.method === "POST").map((c) => c.path)).toEqual([
      "/api/nodes/1/drive/enable",
      "/api/nodes/1/drive/fault-reset",
    ]);
  });
});

describe("the last PP move", () => {
  const move = { target_inc: 393216, queued: 0 };

  it("is not 'moving' once the drive is out of Operation enabled", () => {
    const stale: DriveState = { ...DRIVE, move: { ...move, phase: "moving" } };
    const said = moveText(stale);
    expect(said?.text).not.toContain("moving");
    expect(said?.text).toContain("not reached");
    expect(said?.text).toContain("Switch on disabled");
  });

  it("says why it was interrupted", () => {
    const said = moveText({
      ...DRIVE,
      move: {
        ...move,
        phase: "interrupted",
        message: "stopped by quick stop (controlword bit 2 = 0)",
      },
    });
    expect(said?.text).toBe(
      "Move to 393\u202f216 inc: not reached — stopped by quick stop (controlword bit 2 = 0)",
    );
    expect(said?.tone).toBe("warn");
  });

  it("is moving while the drive is enabled", () => {
    expect(moveText({ ...ENABLED, move: { ...move, phase: "moving" } })?.text).toBe(
      "Move to 393\u202f216 inc: moving",
    );
  });

  it("shows on the page as stopped after a quick stop", async () => {
    render({
      "GET /api/nodes/1/drive": {
        ...DRIVE,
        move: {
          ...move,
          phase: "interrupted",
          message: "stopped by quick stop (controlword bit 2 = 0)",
        },
      },
    });
    const said = await screen.findByTestId("pp-move");
    expect(said.textContent).toContain("not reached — stopped by quick stop");
    expect(said.textContent).not.toContain(": moving");
  });
});

describe("limits and travel", () => {
  it("lists where the travel ends, the simulator's switches marked", () => {
    const rows = travelRows(TRAVEL);
    expect(rows.map((r) => [r.label, r.range])).toEqual([
      ["Limit switches", "−5.000\u00a0rev\u00a0…\u00a05.000\u00a0rev"],
      ["ServoDesk's travel limits", "none"],
    ]);
    expect(rows[0]?.source).toContain("5FF1h");
  });

  it("proposes ServoDesk's travel limits just inside the switches", () => {
    expect(limitsInsideSwitches(TRAVEL)).toEqual({
      ...TRAVEL.limits,
      min_position_rev: -4.9,
      max_position_rev: 4.9,
    });
    expect(limitsInsideSwitches({ ...TRAVEL, travel: null })).toBeNull();
  });

  it("shows the drive's own limits and offers the travel limits", async () => {
    const fetch = render({
      "GET /api/nodes/1/drive": TRAVEL,
      "PUT /api/nodes/1/drive/limits": (request: Request) => request.json(),
    });
    const card = within(await screen.findByRole("region", { name: "Limits in force" }));
    expect(card.getByText("drive's own 300.0 rpm")).toBeTruthy();
    expect(card.getByTestId("drive-limits-source").textContent).toContain("PA-103");
    const travel = within(card.getByRole("table", { name: "Where the travel ends" }));
    expect(travel.getByText("simulator")).toBeTruthy();
    expect(travel.getByText("−5.000 rev … 5.000 rev")).toBeTruthy(); // spaces normalized
    expect(travel.getByText(/no 607Dh Software position limit/)).toBeTruthy();
    await userEvent.click(
      card.getByRole("button", {
        name: /^Set ServoDesk's travel limits to −4\.900\srev\s…\s4\.900\srev$/,
      }),
    );
    await waitFor(() => expect(fetch.calls.some((c) => c.method === "PUT")).toBe(true));
    const put = fetch.calls.find((c) => c.method === "PUT");
    expect(JSON.parse(put?.body ?? "{}")).toMatchObject({
      min_position_rev: -4.9,
      max_position_rev: 4.9,
      max_velocity_rpm: 3000,
    });
  });
});
