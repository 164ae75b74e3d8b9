import { describe, expect, it } from "vitest";

import {
  FIRST_PAGE,
  countsText,
  currentStart,
  formatDuration,
  logClock,
  pageBack,
  pageForward,
  pageLabel,
  parseStats,
  recordingText,
  statItems,
} from "./logText";
import type { LogEvent, RecordingInfo } from "./types";

const event = (seq: number): LogEvent => ({
  seq,
  time: seq,
  frame: seq + 1,
  kind: "sdo",
  node: 1,
  text: "",
  index: null,
  subindex: null,
  code: null,
  data: null,
  polling: false,
});

describe("log text", () => {
  it.each([
    [0, "+0.000 s"],
    [12.3456, "+12.346 s"],
  ])("relative clock %s", (t, text) => {
    expect(logClock(t)).toBe(text);
  });

  it("absolute clock is wall-clock time", () => {
    expect(logClock(1_700_000_000.25)).toMatch(/^\d\d:\d\d:\d\d\.250$/);
  });

  it.each([
    [0.5, "0.500 s"],
    [61.25, "1 min 1.3 s"],
    [3725, "1 h 2 min"],
    [-1, "—"],
  ])("duration %s", (s, text) => {
    expect(formatDuration(s)).toBe(text);
  });

  it("reads the free-form stats defensively", () => {
    const stats = parseStats({
      frames: 1234,
      duration_s: 2.5,
      nodes: [1, 2, "x"],
      counts: { emcy: 1, "sdo-abort": 2, frame: 99, bad: "x" },
      bitrate: 500000,
      bus_load_peak_percent: 12.345,
      bus_load_mean_percent: 3.2,
      events: 40,
    });
    expect(stats.nodes).toEqual([1, 2]);
    expect(stats.counts).toEqual({ emcy: 1, "sdo-abort": 2, frame: 99 });
    expect(statItems(stats)).toEqual([
      { label: "Frames", value: "1,234" },
      { label: "Duration", value: "2.500 s" },
      { label: "Node ids", value: "1, 2" },
      { label: "Bus load", value: "peak 12.3 %, mean 3.2 %" },
      { label: "Bitrate", value: "500 kbit/s" },
      { label: "Events", value: "40" },
    ]);
    expect(countsText(stats.counts)).toBe("sdo-abort 2 · emcy 1");
    expect(parseStats({}).frames).toBe(0);
  });

  it("pages forward and back", () => {
    let pager = FIRST_PAGE;
    expect(currentStart(pager)).toBe(0);
    pager = pageForward(pager, 500);
    pager = pageForward(pager, 1000);
    expect(currentStart(pager)).toBe(1000);
    pager = pageBack(pager);
    expect(currentStart(pager)).toBe(500);
    expect(pageBack(pageBack(pager))).toEqual(FIRST_PAGE);
  });

  it.each([
    [[], null, "No events"],
    [[event(0), event(499)], 1200, "Events 1–500 of 1,200"],
    [[event(500), event(999)], null, "Events 501–1,000"],
  ])("page label %#", (page, total, text) => {
    expect(pageLabel(page, total)).toBe(text);
  });

  it.each([
    [
      { active: false, format: null, file: null, since: null, frames: 0, dropped: 0 },
      "Not recording",
    ],
    [
      { active: true, format: "blf", file: "x.blf", since: 100, frames: 1500, dropped: 0 },
      "Recording BLF: 1,500 frames, 10.000 s",
    ],
    [
      { active: true, format: "log", file: "x.log", since: null, frames: 2, dropped: 3 },
      "Recording LOG: 2 frames (3 dropped)",
    ],
  ] as [RecordingInfo, string][])("recording %#", (info, text) => {
    expect(recordingText(info, 110)).toBe(text);
  });
});
