import { screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { json, stubFetch } from "../../test/fetchStub";
import { ENABLED } from "../../test/fixtures/drive";
import { renderPage } from "../../test/render";
import { IpStreamPanel } from "./IpStreamPanel";
import type { IpStreamResult } from "./types";

afterEach(() => {
  vi.unstubAllGlobals();
});

const REFUSED =
  "node 3: SYNC timing on this computer is unsafe for a 2 ms stream (SYNC jitter 17.69 ms, " +
  "longest interval 19.69 ms over 12 periods of 2 ms; the drive faults after 6 ms without " +
  "SYNC); nothing was sent: choose a longer period or reduce the load on this computer, then " +
  "try again";

const STALLED: IpStreamResult = {
  node: 3,
  trajectory: "point_to_point",
  period_ms: 10,
  points: 14,
  syncs: 14,
  duration_s: 2,
  max_lag_inc: 4135,
  max_lag_rev: 0.0315,
  final_error_inc: 90000,
  sync_jitter_ms: 26.47,
  sync_interval_max_ms: 36.47,
  stalled: true,
  fault: null,
  message:
    "14 set-points at 10 ms; the stream stalled: no SYNC for 36.47 ms, more than 3 periods " +
    "(30 ms); this computer was too busy to keep time",
  state: ENABLED,
};

function panel(): void {
  renderPage(<IpStreamPanel node={3} drive={ENABLED} show={() => undefined} mayCommand />);
}

describe("IP stream panel", () => {
  it("says the stream was refused for unsafe SYNC timing and offers 10 ms", async () => {
    stubFetch({
      "POST /api/nodes/3/drive/ip-stream": json({ error: "sync_unsafe", message: REFUSED }, 409),
    });
    panel();
    await userEvent.click(screen.getByRole("radio", { name: "2 ms" }));
    await userEvent.click(screen.getByRole("button", { name: "Run stream" }));
    const box = await screen.findByTestId("ip-refused");
    expect(box.textContent).toContain("Stream not started: SYNC timing unsafe");
    expect(box.textContent).toContain("SYNC jitter 17.69 ms");
    await userEvent.click(screen.getByRole("button", { name: "Use 10 ms instead" }));
    expect(screen.getByRole<HTMLInputElement>("radio", { name: "10 ms" }).checked).toBe(true);
  });

  it("heads a stalled stream's result as failed", async () => {
    stubFetch({ "POST /api/nodes/3/drive/ip-stream": STALLED });
    panel();
    await userEvent.click(screen.getByRole("button", { name: "Run stream" }));
    const box = await screen.findByRole("alert");
    expect(box.textContent).toContain("Stream failed");
    expect(box.textContent).toContain("no SYNC for 36.47 ms");
  });
});
