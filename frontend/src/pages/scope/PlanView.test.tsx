import { render, screen, within } from "@testing-library/react";
import { describe, expect, it } from "vitest";

import { ApiError } from "../../api/errors";
import { LOAD, OVERSPEED, PLAN, POSITION, STATUSWORD, VELOCITY } from "./fixtures";
import { PlanView } from "./PlanView";

describe("PlanView", () => {
  it("shows each signal's source, the bus load and the notes", () => {
    render(
      <PlanView
        plan={{
          ...PLAN,
          signals: [POSITION, VELOCITY, OVERSPEED, STATUSWORD],
          notes: ["node 3: TPDO5 has no usable CAN id"],
        }}
        checking={false}
        error={null}
        problem={null}
      />,
    );
    const table = screen.getByRole("table", { name: "Signal sources" });
    const row = (name: RegExp): HTMLElement => within(table).getByRole("row", { name });
    expect(row(/6064h:00/).textContent).toContain("TPDO2 · COB-ID 0x281");
    expect(row(/6064h:00/).textContent).toContain("rev");
    const polled = row(/2006h:08/);
    expect(polled.textContent).toContain("SDO polling");
    expect(polled.textContent).toContain("not PDO-mappable in this drive's dictionary");
    expect(row(/6041h:00/).textContent).toContain("added: the CiA 402 state lane");
    const load = screen.getByRole("meter", { name: "Bus load during the capture" });
    expect(load.getAttribute("aria-valuenow")).toBe("53");
    expect(screen.getByText(/265,000 bit\/s of 500 kbit\/s/)).toBeTruthy();
    expect(screen.getByRole("meter", { name: "Node 1 load" })).toBeTruthy();
    expect(within(screen.getByRole("list", { name: "Notes" })).getByText(/TPDO5/)).toBeTruthy();
    expect(screen.getByText("How the load is estimated")).toBeTruthy();
    expect(screen.queryByRole("list", { name: "Problems" })).toBeNull();
  });

  it("lists the problems of a plan that cannot run", () => {
    const problem = "the capture would load the bus to 107 % at a 500 µs SYNC period";
    render(
      <PlanView
        plan={{
          ...PLAN,
          ok: false,
          problems: [problem],
          bus_load: { ...LOAD, percent: 107, over_threshold: true },
        }}
        checking={false}
        error={null}
        problem={null}
      />,
    );
    expect(within(screen.getByRole("list", { name: "Problems" })).getByText(problem)).toBeTruthy();
    const meter = screen.getByRole("meter", { name: "Bus load during the capture" });
    expect(meter.className).toContain("over");
  });

  it("says what is missing before it can check, and shows a failed check in words", () => {
    const { rerender } = render(
      <PlanView plan={null} checking={false} error={null} problem="Pick at least one signal" />,
    );
    expect(screen.getByText("Pick at least one signal.")).toBeTruthy();
    expect(screen.queryByRole("table")).toBeNull();
    rerender(
      <PlanView
        plan={PLAN}
        checking={true}
        error={new ApiError(404, "node_not_found", "Node 9 is not on the bus", null)}
        problem={null}
      />,
    );
    expect(screen.getByRole("alert").textContent).toBe("Node 9 is not on the bus");
    expect(screen.getByText("checking…")).toBeTruthy();
    expect(screen.getByRole("table", { name: "Signal sources" })).toBeTruthy(); // kept, dimmed
  });
});
