import { render, screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { toApiError } from "../api/errors";
import { stubFetch } from "../test/fetchStub";
import { ErrorText } from "./ErrorText";

afterEach(() => {
  vi.unstubAllGlobals();
});

const stopped = toApiError(409, {
  error: "node_stopped",
  message:
    "node 3 is Stopped: SDO is not available in that state — set it Pre-operational or Operational",
  node: 3,
});

describe("ErrorText", () => {
  it("offers to set a Stopped node Pre-operational, then lets the page retry", async () => {
    const fetch = stubFetch({ "POST /api/nodes/3/nmt": { node: 3, nmt_state: "pre-operational" } });
    const retry = vi.fn();
    render(<ErrorText error={stopped} onRetry={retry} />);
    expect(screen.getByRole("alert").textContent).toContain("node 3 is Stopped");

    await userEvent.click(screen.getByRole("button", { name: "Set node 3 Pre-operational" }));

    expect(fetch.calls).toEqual([
      { method: "POST", path: "/api/nodes/3/nmt", body: '{"command":"pre-operational"}' },
    ]);
    expect(retry).toHaveBeenCalledOnce();
  });

  it("offers nothing for other errors", () => {
    render(<ErrorText error={toApiError(504, { error: "timeout", message: "no answer" })} />);
    expect(screen.queryByRole("button")).toBeNull();
    expect(screen.getByRole("alert").textContent).toBe("no answer");
  });
});
