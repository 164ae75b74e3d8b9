import { describe, expect, it } from "vitest";

import type { TimelineEvent } from "../../api/timeline";
import {
  EMPTY_TIMELINE,
  TIMELINE_MAX,
  addEvents,
  addNewer,
  addOlder,
  firstPage,
  matchesFilter,
  timelineQuery,
} from "./timelineState";

const ev = (id: number): TimelineEvent => ({
  id,
  time: 1000 + id,
  kind: "nmt",
  node: 1,
  message: `event ${id}`,
  data: {},
});
const ids = (events: TimelineEvent[]): number[] => events.map((e) => e.id);

describe("timeline state", () => {
  it("starts from the newest-first page", () => {
    const t = firstPage({ events: [ev(9), ev(8)], next: 8 });
    expect(ids(t.events)).toEqual([9, 8]);
    expect(t.newest).toBe(9);
    expect(t.older).toBe(8);
    expect(firstPage({ events: [], next: null })).toEqual({ events: [], newest: 0, older: null });
  });

  it.each([
    ["new events go on top, newest first", [ev(10), ev(11)], [11, 10, 9, 8], 11],
    ["duplicates are dropped", [ev(9), ev(10)], [10, 9, 8], 10],
    ["nothing new keeps the list", [], [9, 8], 9],
  ])("%s", (_, polled, expected, newest) => {
    const start = firstPage({ events: [ev(9), ev(8)], next: null });
    const t = addNewer(start, { events: polled, next: 11 });
    expect(ids(t.events)).toEqual(expected);
    expect(t.newest).toBe(newest);
  });

  it("merges a catch-up that arrives after live events by id, once each", () => {
    let t = firstPage({ events: [ev(9), ev(8)], next: null });
    t = addEvents(t, [ev(12)]); // live, after a gap (10, 11 missed)
    t = addEvents(t, [ev(12)]); // the same event again
    t = addNewer(t, { events: [ev(10), ev(11), ev(12)], next: 12 }); // the catch-up
    expect(ids(t.events)).toEqual([12, 11, 10, 9, 8]);
    expect(t.newest).toBe(12);
  });

  it.each([
    [{ node: null, kind: null }, true],
    [{ node: 1, kind: "nmt" as const }, true],
    [{ node: 2, kind: null }, false],
    [{ node: null, kind: "emcy" as const }, false],
  ])("filter %# matches a live event: %s", (filter, expected) => {
    expect(matchesFilter(filter, ev(1))).toBe(expected);
  });

  it("pages back for older events", () => {
    const t = addOlder(firstPage({ events: [ev(9), ev(8)], next: 8 }), {
      events: [ev(7), ev(6)],
      next: null,
    });
    expect(ids(t.events)).toEqual([9, 8, 7, 6]);
    expect(t.older).toBeNull();
  });

  it("stays bounded, and older… continues below what is kept", () => {
    const many = Array.from({ length: TIMELINE_MAX }, (_, i) => ev(TIMELINE_MAX - i));
    const t = addNewer(
      { events: many, newest: TIMELINE_MAX, older: null },
      { events: [ev(TIMELINE_MAX + 1)], next: null },
    );
    expect(t.events).toHaveLength(TIMELINE_MAX);
    expect(t.events[0]?.id).toBe(TIMELINE_MAX + 1);
    expect(t.older).toBe(2);
  });

  it.each([
    [{ node: null, kind: null }, {}, { limit: 50 }],
    [{ node: 2, kind: null }, { since: 5 }, { node: 2, since: 5, limit: 50 }],
    [{ node: null, kind: "emcy" as const }, { before: 7 }, { kind: "emcy", before: 7, limit: 50 }],
  ])("query %#", (filter, cursor, query) => {
    expect(timelineQuery(filter, cursor)).toEqual(query);
  });

  it("has an empty start", () => {
    expect(EMPTY_TIMELINE.events).toEqual([]);
  });
});
