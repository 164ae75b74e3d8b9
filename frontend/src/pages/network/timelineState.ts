// The live timeline's list: newest first, fed by the WebSocket's `timeline` events, caught up
// with `since` the newest id after a gap, and paged back for older ones (`before` the oldest).
// Pure, so the merging is table-tested.
import type { EventKind, TimelineEvent, TimelinePage } from "../../api/timeline";
import type { MessageKey } from "../../i18n";

export const TIMELINE_PAGE = 50;
/** Keep the list bounded however long the page stays open. */
export const TIMELINE_MAX = 2000;

export interface TimelineFilter {
  node: number | null;
  kind: EventKind | null;
  /** Also the events of other buses (another server on this data directory, an earlier bus);
   * by default the server lists the connected bus's only. */
  allBuses?: boolean;
}

export interface Timeline {
  events: TimelineEvent[];
  /** Highest id seen: the `since` of the next poll (null before the first page). */
  newest: number | null;
  /** `before` for "older…"; null when the first page showed everything. */
  older: number | null;
}

export const EMPTY_TIMELINE: Timeline = { events: [], newest: null, older: null };

/** The first page (newest first) starts the list. */
export function firstPage(page: TimelinePage): Timeline {
  return { events: page.events, newest: page.events[0]?.id ?? 0, older: page.next };
}

/** A `since` page (oldest first) goes on top, without duplicates. */
export function addNewer(timeline: Timeline, page: TimelinePage): Timeline {
  return addEvents(timeline, page.events);
}

/** Newer events (live or fetched, any order) merge in by id, newest first, without duplicates:
 * a catch-up answer that arrives after live events still lands below them. */
export function addEvents(timeline: Timeline, incoming: readonly TimelineEvent[]): Timeline {
  const known = new Set(timeline.events.map((e) => e.id));
  const fresh: TimelineEvent[] = [];
  for (const event of incoming) {
    if (known.has(event.id)) continue;
    known.add(event.id);
    fresh.push(event);
  }
  if (fresh.length === 0) return timeline;
  const events = [...fresh, ...timeline.events].sort((a, b) => b.id - a.id).slice(0, TIMELINE_MAX);
  const dropped = events.length < fresh.length + timeline.events.length;
  return {
    events,
    newest: Math.max(timeline.newest ?? 0, ...fresh.map((e) => e.id)),
    // trimmed at the bottom: "older…" continues from what is still shown
    older: dropped ? (events[events.length - 1]?.id ?? null) : timeline.older,
  };
}

/** An "older…" page (newest first) goes below. */
export function addOlder(timeline: Timeline, page: TimelinePage): Timeline {
  const known = new Set(timeline.events.map((e) => e.id));
  return {
    ...timeline,
    events: [...timeline.events, ...page.events.filter((e) => !known.has(e.id))],
    older: page.next,
  };
}

/** Whether a live event belongs in a list filtered by `filter` (as GET /api/events filters). */
export function matchesFilter(filter: TimelineFilter, event: TimelineEvent): boolean {
  return (
    (filter.node === null || event.node === filter.node) &&
    (filter.kind === null || event.kind === filter.kind)
  );
}

/** The route's query for a filter and a cursor. */
export function timelineQuery(
  filter: TimelineFilter,
  cursor: { since?: number; before?: number } = {},
): {
  node?: number;
  kind?: EventKind;
  since?: number;
  before?: number;
  limit: number;
  all_buses?: boolean;
} {
  return {
    ...(filter.node === null ? {} : { node: filter.node }),
    ...(filter.kind === null ? {} : { kind: filter.kind }),
    ...(filter.allBuses ? { all_buses: true } : {}),
    ...cursor,
    limit: TIMELINE_PAGE,
  };
}

/** The kinds a user filters by, in words (catalogue keys). */
export const KIND_LABELS: Record<EventKind, MessageKey> = {
  "boot-up": "network.timeline.filter.bootUp",
  "node-lost": "network.timeline.filter.nodeLost",
  "node-back": "network.timeline.filter.nodeBack",
  nmt: "network.timeline.filter.nmt",
  bus: "network.timeline.filter.bus",
  emcy: "network.timeline.filter.emcy",
  "fault-cleared": "network.timeline.filter.faultCleared",
  "fault-reset": "network.timeline.filter.faultReset",
  "sdo-abort": "network.timeline.filter.sdoAbort",
  "cia402-state": "network.timeline.filter.cia402State",
  "tool-write": "network.timeline.filter.toolWrite",
  recording: "network.timeline.filter.recording",
  dropped: "network.timeline.filter.dropped",
};

/** One event's kind on its badge (catalogue keys; English shows the kind's own id). */
const KIND_BADGES: Record<EventKind, MessageKey> = {
  "boot-up": "network.timeline.badge.bootUp",
  "node-lost": "network.timeline.badge.nodeLost",
  "node-back": "network.timeline.badge.nodeBack",
  nmt: "network.timeline.badge.nmt",
  bus: "network.timeline.badge.bus",
  emcy: "network.timeline.badge.emcy",
  "fault-cleared": "network.timeline.badge.faultCleared",
  "fault-reset": "network.timeline.badge.faultReset",
  "sdo-abort": "network.timeline.badge.sdoAbort",
  "cia402-state": "network.timeline.badge.cia402State",
  "tool-write": "network.timeline.badge.toolWrite",
  recording: "network.timeline.badge.recording",
  dropped: "network.timeline.badge.dropped",
};

/** The badge's key of an event's kind; null for a kind this app does not know yet (the server
 * may add one): that shows as the server names it. */
export function kindBadgeKey(kind: string): MessageKey | null {
  return Object.hasOwn(KIND_BADGES, kind) ? KIND_BADGES[kind as EventKind] : null;
}
