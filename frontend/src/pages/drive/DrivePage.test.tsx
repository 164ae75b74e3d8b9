import { fireEvent, screen, waitFor, within } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { CLIENT_ID } from "../../api/clientId";
import { LiveStore } from "../../live/store";
import { json, stubFetch, type Handler } from "../../test/fetchStub";
import { CONTROLLER, DRIVE, ENABLED, METHODS } from "../../test/fixtures/drive";
import { renderPage } from "../../test/render";
import { DrivePage } from "./DrivePage";
import type { DriveState } from "./types";

afterEach(() => {
  vi.unstubAllGlobals();
});

const BASE: Record<string, Handler | object> = {
  "GET /api/nodes/1/drive": DRIVE,
  "GET /api/nodes/1/drive/controller": CONTROLLER,
  "GET /api/nodes/1/drive/homing-methods": METHODS,
};

/** The drive as the server keeps it: an action's answer is also what the next polls read (the
 * page polls every 200 ms, so a static GET answer would undo the action on screen). */
function fakeDrive(initial: DriveState): {
  get: () => DriveState;
  answer: (state: DriveState) => () => DriveState;
} {
  let current = initial;
  return {
    get: () => current,
    answer: (state) => () => {
      current = state;
      return state;
    },
  };
}

function render(routes: Record<string, Handler | object> = {}, store = new LiveStore()) {
  const fetch = stubFetch({ ...BASE, ...routes });
  renderPage(<DrivePage node={1} />, "/nodes/1/drive", store);
  return { fetch, store };
}

describe("DrivePage", () => {
  it("shows the state on the diagram, the statusword lamps and the values", async () => {
    render();
    const diagram = await screen.findByRole("img", {
      name: /CiA 402 state diagram: Switch on disabled/,
    });
    expect(
      diagram.querySelector('[data-state="switch_on_disabled"]')?.getAttribute("class"),
    ).toContain("current");
    expect(screen.getByTestId("statusword").textContent).toBe("6041h = 0250h");
    const bits = within(screen.getByRole("list", { name: "Statusword bits" }));
    expect(bits.getByLabelText("Switch on disabled: on")).toBeTruthy();
    expect(bits.getByLabelText("Operation enabled: off")).toBeTruthy();
    expect(screen.getByLabelText("Home switch (HW): on")).toBeTruthy();
    expect(screen.getByTestId("position").textContent).toContain("1.000 rev");
    expect(screen.getByTestId("mode").textContent).toBe("Profile position (PP)");
    // where each value comes from: the drive's frames or an SDO read, and how to map it
    expect(screen.getByTestId("source-position").textContent).toBe("TPDO2");
    expect(screen.getByTestId("source-velocity").textContent).toBe("SDO");
    expect(screen.getByTestId("source-hint").textContent).toContain("Map them in a TPDO");
    expect(await screen.findByTestId("heartbeat-protection")).toBeTruthy();
    expect(screen.getByTestId("controller").textContent).toBe("Nobody controls this drive");
    // commands that take a transition from here are open, with their numbers
    const shutdown = screen.getByRole("button", { name: "Shutdown" });
    expect(shutdown).toHaveProperty("disabled", false);
    expect(shutdown.title).toBe("Controlword 0006h: transition 2");
    expect(screen.getByRole("button", { name: "Fault reset" })).toHaveProperty("disabled", true);
  });

  it("answers why it won't enable, with the way out", async () => {
    const { fetch } = render({
      "POST /api/nodes/1/drive/enable": json(
        {
          error: "enable_blocked",
          message: "node 1 does not enable",
          reasons: [
            { code: "nmt_not_operational", message: "Node 1 is Pre-operational: PDOs are off" },
            { code: "voltage_disabled", message: "Bit 4 voltage enabled is 0: no DC bus" },
          ],
          state: DRIVE,
        },
        409,
      ),
    });
    await userEvent.click(await screen.findByRole("button", { name: "Enable" }));
    const why = await screen.findByRole("alert", { name: "Why won't it enable?" });
    expect(within(why).getByText("Node 1 is Pre-operational: PDOs are off")).toBeTruthy();
    expect(within(why).getByText("Bit 4 voltage enabled is 0: no DC bus")).toBeTruthy();
    expect(within(why).getByRole("button", { name: /Start node 1/ })).toBeTruthy();
    const call = fetch.calls.find((c) => c.path === "/api/nodes/1/drive/enable");
    expect(call).toBeDefined();
  });

  it("enables and highlights the transition just taken", async () => {
    const drive = fakeDrive(DRIVE);
    const { fetch } = render({
      "GET /api/nodes/1/drive": drive.get,
      "POST /api/nodes/1/drive/enable": drive.answer(ENABLED),
    });
    await userEvent.click(await screen.findByRole("button", { name: "Enable" }));
    await screen.findByRole("img", { name: /Operation enabled, after transition 4/ });
    const arrow = document.querySelector('[data-transition="4"]');
    expect(arrow?.getAttribute("class")).toContain("active");
    expect(screen.getByTestId("drive-state").textContent).toBe("Operation enabled");
    expect(fetch.calls.some((c) => c.path === "/api/nodes/1/drive/enable")).toBe(true);
  });

  it("keeps an action's answer when a poll sent before it answers after it", async () => {
    let polls = 0;
    let release: (() => void) | undefined;
    render({
      // the first poll answers; the second is held back until the enable was answered, and
      // then answers the state from before; later polls never answer
      "GET /api/nodes/1/drive": () => {
        polls += 1;
        if (polls === 1) return DRIVE;
        if (polls === 2) return new Promise((resolve) => (release = () => resolve(DRIVE)));
        return new Promise(() => undefined);
      },
      "POST /api/nodes/1/drive/enable": ENABLED,
    });
    const enable = await screen.findByRole("button", { name: "Enable" });
    await waitFor(() => expect(release).toBeDefined());
    await userEvent.click(enable);
    await screen.findByRole("img", { name: /Operation enabled, after transition 4/ });
    release?.();
    await new Promise((resolve) => setTimeout(resolve, 50));
    expect(screen.getByTestId("drive-state").textContent).toBe("Operation enabled");
  });

  it("sends the tab's client id with every call", async () => {
    const headers: string[] = [];
    render({
      "GET /api/nodes/1/drive": (request: Request) => {
        headers.push(request.headers.get("X-Client-Id") ?? "");
        return DRIVE;
      },
    });
    await screen.findByTestId("statusword");
    expect(headers[0]).toBe(CLIENT_ID);
  });

  it("quick stops in one click", async () => {
    const drive = fakeDrive(DRIVE);
    const { fetch } = render({
      "GET /api/nodes/1/drive": drive.get,
      "POST /api/nodes/1/drive/quick-stop": drive.answer({
        ...ENABLED,
        state: "quick_stop_active",
        statusword: 0x0217,
      }),
    });
    await userEvent.click(screen.getByRole("button", { name: "Quick stop node 1" }));
    expect(await screen.findByText("Quick stop active", { selector: ".badge" })).toBeTruthy();
    expect(fetch.calls.filter((c) => c.path === "/api/nodes/1/drive/quick-stop")).toHaveLength(1);
  });

  it("offers take over when another tab controls the drive", async () => {
    const { fetch } = render({
      "GET /api/nodes/1/drive/controller": {
        ...CONTROLLER,
        holder: { client_id: "other", name: "Firefox tab 9f3a", since: 1 },
      },
      "POST /api/nodes/1/drive/controller": {
        ...CONTROLLER,
        holder: { client_id: CLIENT_ID, since: 2 },
        you: true,
      },
    });
    expect(await screen.findByText("Controlled by Firefox tab 9f3a")).toBeTruthy();
    expect(screen.getByRole("button", { name: "Enable" })).toHaveProperty("disabled", true);
    await userEvent.click(screen.getByRole("button", { name: "Take over" }));
    expect(await screen.findByText("You control this drive")).toBeTruthy();
    const body = fetch.calls.find(
      (c) => c.method === "POST" && c.path.endsWith("/controller"),
    )?.body;
    expect(JSON.parse(body ?? "{}")).toMatchObject({ take_over: true });
  });

  it("jogs PV only while the button is held", async () => {
    let keepalives = 0;
    const { fetch } = render({
      "GET /api/nodes/1/drive": ENABLED,
      "POST /api/nodes/1/jog": {
        jog_id: "j1",
        node: 1,
        mode: "pv",
        value: 60,
        keepalive_ms: 300,
        state: "running",
      },
      "POST /api/jog/j1/keepalive": () => {
        keepalives += 1;
        return { jog_id: "j1" };
      },
      "DELETE /api/jog/j1": { jog_id: "j1", state: "stopped" },
    });
    await userEvent.click(await screen.findByRole("tab", { name: "Profile velocity (PV)" }));
    const plus = screen.getByRole("button", { name: /Hold \+60 rpm/ });
    fireEvent.pointerDown(plus, { button: 0 });
    await waitFor(() => expect(keepalives).toBeGreaterThanOrEqual(2), { timeout: 1500 });
    expect(screen.getByTestId("jog-pv-status").textContent).toContain("Moving");
    fireEvent.pointerUp(plus);
    await waitFor(() => expect(fetch.calls.some((c) => c.method === "DELETE")).toBe(true));
    const start = fetch.calls.find((c) => c.path === "/api/nodes/1/jog");
    expect(JSON.parse(start?.body ?? "{}")).toEqual({
      mode: "pv",
      velocity_rpm: 60,
      keepalive_ms: 300,
      acceleration_rpm_s: 1000,
    });
    const after = keepalives;
    await new Promise((resolve) => setTimeout(resolve, 250));
    expect(keepalives).toBe(after);
  });

  it("jogs PV at the chosen acceleration", async () => {
    const { fetch } = render({
      "GET /api/nodes/1/drive": ENABLED,
      "POST /api/nodes/1/jog": {
        jog_id: "j2",
        node: 1,
        mode: "pv",
        value: 60,
        keepalive_ms: 300,
        state: "running",
      },
      "POST /api/jog/j2/keepalive": { jog_id: "j2" },
      "DELETE /api/jog/j2": { jog_id: "j2", state: "stopped" },
    });
    await userEvent.click(await screen.findByRole("tab", { name: "Profile velocity (PV)" }));
    const jog = within(screen.getByRole("region", { name: "Jog" }));
    const accel = jog.getByLabelText("Acceleration (rpm/s)");
    await userEvent.clear(accel);
    await userEvent.type(accel, "250");
    const minus = screen.getByRole("button", { name: /Hold −60 rpm/ });
    fireEvent.pointerDown(minus, { button: 0 });
    await waitFor(() => expect(fetch.calls.some((c) => c.path === "/api/nodes/1/jog")).toBe(true));
    fireEvent.pointerUp(minus);
    const start = fetch.calls.find((c) => c.path === "/api/nodes/1/jog");
    expect(JSON.parse(start?.body ?? "{}")).toMatchObject({
      mode: "pv",
      velocity_rpm: -60,
      acceleration_rpm_s: 250,
    });
    await userEvent.clear(accel);
    await userEvent.type(accel, "0");
    expect(screen.getByText("Acceleration (rpm/s): Must be above 0")).toBeTruthy();
    expect(minus).toHaveProperty("disabled", true);
  });

  it("jogs PT with a torque slope and ServoDesk's own speed cap, and says what limits the speed", async () => {
    const { fetch } = render({
      "GET /api/nodes/1/drive": ENABLED,
      "POST /api/nodes/1/jog": {
        jog_id: "j3",
        node: 1,
        mode: "pt",
        value: 10,
        keepalive_ms: 300,
        state: "running",
      },
      "POST /api/jog/j3/keepalive": { jog_id: "j3" },
      "DELETE /api/jog/j3": { jog_id: "j3", state: "stopped" },
    });
    await userEvent.click(await screen.findByRole("tab", { name: "Profile torque (PT)" }));
    expect(screen.getByTestId("jog-pt-speed-limit").textContent).toContain(
      "the drive itself holds the speed at 6000 rpm (2006h:08 PA-103 Maximum speed)",
    );
    const cap = within(screen.getByRole("region", { name: "Jog" })).getByLabelText(
      "Speed cap (rpm)",
    );
    expect((cap as HTMLInputElement).value).toBe("300");
    await userEvent.clear(cap);
    await userEvent.type(cap, "7000");
    expect(screen.getByText(/Speed cap: /)).toBeTruthy(); // above the speed limit in force
    await userEvent.clear(cap);
    await userEvent.type(cap, "150");
    const slope = within(screen.getByRole("region", { name: "Jog" })).getByLabelText(
      "Torque slope (%/s)",
    );
    await userEvent.clear(slope);
    await userEvent.type(slope, "50");
    expect(screen.getByText("Torque slope (%/s): At least 100")).toBeTruthy();
    await userEvent.clear(slope);
    await userEvent.type(slope, "500");
    const plus = screen.getByRole("button", { name: /Hold \+10 %/ });
    fireEvent.pointerDown(plus, { button: 0 });
    await waitFor(() => expect(fetch.calls.some((c) => c.path === "/api/nodes/1/jog")).toBe(true));
    fireEvent.pointerUp(plus);
    const start = fetch.calls.find((c) => c.path === "/api/nodes/1/jog");
    expect(JSON.parse(start?.body ?? "{}")).toMatchObject({
      mode: "pt",
      torque_pct: 10,
      torque_slope_pct_s: 500,
      speed_cap_rpm: 150,
    });
  });

  it("sends every transition button through the drive command route", async () => {
    let commands = 0;
    const drive = fakeDrive(ENABLED);
    const switchedOn = drive.answer({
      ...ENABLED,
      state: "switched_on",
      state_label: "Switched on",
      statusword: 0x0233,
      controlword: 0x0007,
      last_transition: "disable operation (5)",
    });
    const { fetch } = render({
      "GET /api/nodes/1/drive": drive.get,
      // the first command (disable operation) takes transition 5, the second is refused
      "POST /api/nodes/1/drive/command": () =>
        (commands += 1) === 1
          ? switchedOn()
          : json(
              {
                error: "enable_blocked",
                message: "node 1 does not take shutdown",
                reasons: [
                  { code: "fault_reset_high", message: "controlword bit 7 (fault reset) is 1" },
                ],
                state: { ...ENABLED, state: "switched_on", statusword: 0x0233 },
              },
              409,
            ),
    });
    await userEvent.click(await screen.findByRole("button", { name: "Disable operation" }));
    expect(await screen.findByText("Switched on", { selector: ".badge" })).toBeTruthy();
    const sent = fetch.calls.filter((c) => c.path === "/api/nodes/1/drive/command");
    expect(sent.map((c) => JSON.parse(c.body) as unknown)).toEqual([
      { command: "disable_operation" },
    ]);
    expect(fetch.calls.some((c) => c.path.includes("/sdo/"))).toBe(false);
    await userEvent.click(await screen.findByRole("button", { name: "Shutdown" }));
    const why = await screen.findByRole("alert", { name: "Why didn't Shutdown happen?" });
    expect(within(why).getByText("controlword bit 7 (fault reset) is 1")).toBeTruthy();
  });

  it("draws each homing method and starts the picked one", async () => {
    const drive = fakeDrive(ENABLED);
    const { fetch } = render({
      "GET /api/nodes/1/drive": drive.get,
      "POST /api/nodes/1/drive/home": drive.answer({
        ...ENABLED,
        homing: { method: 35, phase: "attained", message: "", position_inc: 0 },
      }),
    });
    const diagram17 = await screen.findByTestId("homing-diagram-17");
    expect(diagram17.getAttribute("aria-label")).toContain(
      "fast negative until negative limit switch rises",
    );
    expect(screen.getByTestId("homing-diagram-35").getAttribute("aria-label")).toContain(
      "no motion",
    );
    await userEvent.click(screen.getByRole("radio", { name: /35 Current position/ }));
    await userEvent.click(screen.getByRole("button", { name: "Start homing (method 35)" }));
    expect(await screen.findByText("Homing attained")).toBeTruthy();
    const body: unknown = JSON.parse(
      fetch.calls.find((c) => c.path.endsWith("/home"))?.body ?? "{}",
    );
    expect(body).toEqual({
      method: 35,
      fast_rpm: 100,
      slow_rpm: 20,
      acceleration_rpm_s: 500,
      offset_inc: 0,
    });
  });

  it("takes pushed drive states from the socket", async () => {
    const store = new LiveStore();
    const sent: unknown[] = [];
    store.setLink({ state: "open", attempt: 0, retryAt: null });
    store.setSender((m) => sent.push(m) > 0);
    render({}, store);
    await screen.findByTestId("statusword");
    expect(sent).toContainEqual({ type: "watch_drive", node: 1 });
    store.apply({ type: "drive_state", state: { ...ENABLED, statusword: 0x1637 } });
    expect(await screen.findByText("6041h = 1637h")).toBeTruthy();
  });

  it("says Stopping while a stopped jog's axis still turns, and why the server stopped it", async () => {
    const store = new LiveStore();
    store.setLink({ state: "open", attempt: 0, retryAt: null });
    store.setSender(() => true);
    render({ "GET /api/nodes/1/drive": ENABLED }, store);
    await userEvent.click(await screen.findByRole("tab", { name: "Profile torque (PT)" }));
    const jog = {
      jog_id: "j9",
      node: 1,
      mode: "pt" as const,
      value: 2,
      keepalive_ms: 300,
      owner: "tab",
    };
    const why = "EMCY 8613h from the drive";
    store.apply({ type: "jog_stopped", jog: { ...jog, state: "stopping", stop_reason: why } });
    store.apply({ type: "drive_state", state: { ...ENABLED, velocity_rpm: 462 } });
    const status = screen.getByTestId("jog-pt-status");
    await waitFor(() => expect(status.textContent).toContain("Stopping"));
    expect(screen.getByTestId("jog-pt-stop-reason").textContent).toContain(why);
    store.apply({ type: "jog_stopped", jog: { ...jog, state: "stopped", stop_reason: why } });
    store.apply({ type: "drive_state", state: { ...ENABLED, velocity_rpm: 0 } });
    await waitFor(() => expect(status.textContent).toMatch(/^Stopped/));
    expect(screen.getByTestId("jog-pt-stop-reason").textContent).toContain(why);
  });
});
