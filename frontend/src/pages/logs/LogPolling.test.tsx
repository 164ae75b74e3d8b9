import { screen } from "@testing-library/react";
import userEvent from "@testing-library/user-event";
import { afterEach, describe, expect, it, vi } from "vitest";

import { stubFetch } from "../../test/fetchStub";
import { renderPage } from "../../test/render";
import { LogsPage } from "./LogsPage";
import type { LogEvent } from "./types";

afterEach(() => {
  vi.unstubAllGlobals();
});

const event = (seq: number, text: string, polling: boolean): LogEvent => ({
  seq,
  time: seq / 10,
  frame: seq + 1,
  kind: "sdo",
  node: 1,
  text,
  index: 0x6041,
  subindex: 0,
  code: null,
  data: null,
  polling,
});

const decoded = {
  id: "poll1",
  name: "polled.log",
  summary: ["3 frames over 0.200 s (+0.000 s – +0.200 s) from node 1."],
  stats: { frames: 3, duration_s: 0.2, nodes: [1], counts: { sdo: 3 }, events: 3 },
  events: [
    event(0, "node 1 SDO read 6041:00 = poll", true),
    event(1, "node 1 SDO write 6060:00 = 1", false),
    event(2, "node 1 SDO read 6041:00 = poll again", true),
  ],
  next: null,
};
const recording = { active: false, format: null, file: null, since: null, frames: 0, dropped: 0 };

describe("Logs page: the tool's own polling", () => {
  it("hides SDO polling reads on request and shows them again", async () => {
    const stub = stubFetch({
      "GET /api/recording": recording,
      "POST /api/logs/decode": decoded,
      "GET /api/logs/poll1/events": (request: Request) =>
        new URL(request.url).searchParams.get("hide_polling") === "true"
          ? { events: decoded.events.filter((e) => !e.polling), next: null }
          : { events: decoded.events, next: null },
    });
    renderPage(<LogsPage />, "/logs");
    await userEvent.upload(screen.getByLabelText("Choose CAN log…"), new File(["x"], "polled.log"));
    expect(await screen.findByText("node 1 SDO read 6041:00 = poll")).toBeTruthy();

    await userEvent.click(screen.getByLabelText("Hide ServoDesk's own polling"));
    expect(await screen.findByText("node 1 SDO write 6060:00 = 1")).toBeTruthy();
    expect(screen.queryByText("node 1 SDO read 6041:00 = poll")).toBeNull();
    expect(
      stub.urls.some((u) =>
        u.includes("/api/logs/poll1/events?since=0&limit=500&hide_polling=true"),
      ),
    ).toBe(true);

    await userEvent.click(screen.getByLabelText("Hide ServoDesk's own polling"));
    expect(await screen.findByText("node 1 SDO read 6041:00 = poll")).toBeTruthy();
  });

  it("names nodes' drives for the decode", async () => {
    const stub = stubFetch({ "GET /api/recording": recording, "POST /api/logs/decode": decoded });
    renderPage(<LogsPage />, "/logs");
    await userEvent.type(screen.getByLabelText("Drives (optional)"), "1=mdi-s1c");
    await userEvent.upload(screen.getByLabelText("Choose CAN log…"), new File(["x"], "polled.log"));
    await screen.findByRole("list", { name: "Summary" });
    const post = stub.calls.find((c) => c.path === "/api/logs/decode");
    expect(post?.body).toContain('name="profiles"');
    expect(post?.body).toContain("1=mdi-s1c");
  });
});
