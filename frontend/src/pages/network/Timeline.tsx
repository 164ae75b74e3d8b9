import { useCallback, useEffect, useRef, useState, type ReactNode } from "react";

import { api, call } from "../../api/client";
import { asApiError, type ApiError } from "../../api/errors";
import type { EventKind, TimelinePage } from "../../api/timeline";
import { ErrorText } from "../../components/ErrorText";
import { EventList } from "../../components/EventList";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { eventText } from "../../lib/eventText";
import { formatClock } from "../../lib/format";
import { useApi } from "../../lib/useApi";
import { usePoll } from "../../lib/usePoll";
import { useLive, useLiveStore } from "../../live/context";
import {
  EMPTY_TIMELINE,
  KIND_LABELS,
  TIMELINE_PAGE,
  addEvents,
  addNewer,
  addOlder,
  firstPage,
  kindBadgeKey,
  matchesFilter,
  timelineQuery,
  type Timeline as TimelineList,
  type TimelineFilter,
} from "./timelineState";

/** Safety refresh (`since` the synced id) besides the WebSocket's `timeline` events. */
export const TIMELINE_REFRESH_MS = 15_000;

function fetchPage(
  query: ReturnType<typeof timelineQuery>,
  signal?: AbortSignal,
): Promise<TimelinePage> {
  return call(api.GET("/api/events", { params: { query }, signal }));
}

/** What happened on the bus and in the tool, newest first: filter by node and kind, page back
 * with "older…"; new events arrive on the WebSocket. */
export function Timeline(): ReactNode {
  const { t } = useTranslation();
  const nodes = useLive((s) => s.infos.map((i) => i.node).join(","));
  const [filter, setFilter] = useState<TimelineFilter>({ node: null, kind: null });
  return (
    <>
      <div className="inline timeline-filters">
        <label htmlFor="timeline-node" className="muted small">
          {t("network.timeline.node")}
        </label>
        <select
          id="timeline-node"
          value={filter.node ?? ""}
          onChange={(e) =>
            setFilter({ ...filter, node: e.target.value ? Number(e.target.value) : null })
          }
        >
          <option value="">{t("network.timeline.allNodes")}</option>
          {nodes
            .split(",")
            .filter(Boolean)
            .map((n) => (
              <option key={n} value={n}>
                {t("network.timeline.nodeOption", { node: n })}
              </option>
            ))}
        </select>
        <label htmlFor="timeline-kind" className="muted small">
          {t("network.timeline.kind")}
        </label>
        <select
          id="timeline-kind"
          value={filter.kind ?? ""}
          onChange={(e) =>
            setFilter({ ...filter, kind: (e.target.value || null) as EventKind | null })
          }
        >
          <option value="">{t("network.timeline.allKinds")}</option>
          {(Object.keys(KIND_LABELS) as EventKind[]).map((kind) => (
            <option key={kind} value={kind}>
              {t(KIND_LABELS[kind])}
            </option>
          ))}
        </select>
        <label className="check small" title={t("network.timeline.otherBusesTitle")}>
          <input
            type="checkbox"
            checked={filter.allBuses ?? false}
            onChange={(e) => setFilter({ ...filter, allBuses: e.target.checked })}
          />
          {t("network.timeline.otherBuses")}
        </label>
      </div>
      <TimelineList
        key={`${filter.node}-${filter.kind}-${String(filter.allBuses ?? false)}`}
        filter={filter}
      />
    </>
  );
}

/** One filter's list: the first page, then the WebSocket's `timeline` events that match, a
 * `since` catch-up after a gap in their ids or a reconnect, and "older…" pages. */
function TimelineList({ filter }: { filter: TimelineFilter }): ReactNode {
  const { t } = useTranslation();
  const store = useLiveStore();
  const open = useLive((s) => s.link.state === "open");
  const first = useApi((signal) => fetchPage(timelineQuery(filter), signal), "timeline-first");
  const [added, setAdded] = useState<TimelineList | null>(null);
  const [error, setError] = useState<ApiError | null>(null);
  const [busy, setBusy] = useState(false);
  const list = added ?? (first.data ? firstPage(first.data) : EMPTY_TIMELINE);
  const listRef = useRef(list);
  /** Every matching event up to this id is listed (null before the first page). */
  const synced = useRef<number | null>(null);
  /** The highest id the socket delivered (any filter). */
  const streamMax = useRef(0);
  const fetching = useRef(false);
  const again = useRef(false);
  /** A catch-up asked for before the first page was back (the socket opened meanwhile: it
   * did not deliver what was published before, which the first page may have missed too). */
  const deferred = useRef(false);
  const alive = useRef(true);

  const catchUp = useCallback(async (): Promise<void> => {
    if (synced.current === null) {
      deferred.current = true; // run once the first page is in
      return;
    }
    if (fetching.current) {
      again.current = true;
      return;
    }
    fetching.current = true;
    again.current = false;
    /** Whether a gap (or reconnect) asked for another round meanwhile; resets the request. */
    const more = (): boolean => {
      const wanted = again.current;
      again.current = false;
      return wanted;
    };
    try {
      do {
        const from = synced.current; // set once, never unset
        const reached = streamMax.current;
        let since = from;
        for (;;) {
          const page = await fetchPage(timelineQuery(filter, { since }));
          if (!alive.current) return;
          setAdded((old) => addNewer(old ?? listRef.current, page));
          setError(null);
          const next = page.next ?? since;
          if (page.events.length < TIMELINE_PAGE || next <= since) break;
          since = next;
        }
        // everything published before the first request is in: that includes what the
        // socket had delivered by then
        synced.current = Math.max(synced.current, since, reached);
      } while (more());
    } catch (caught) {
      if (alive.current) setError(asApiError(caught));
    } finally {
      fetching.current = false;
    }
  }, [filter]);

  useEffect(() => {
    listRef.current = list;
    if (synced.current === null && list.newest !== null) {
      synced.current = list.newest;
      // events the socket delivered before the first page came back, or a socket that opened
      // meanwhile: fetch what the first page missed
      if (streamMax.current > list.newest || deferred.current) {
        deferred.current = false;
        void catchUp();
      }
    }
  });

  useEffect(() => {
    alive.current = true;
    const unsubscribe = store.subscribeTimeline((event) => {
      streamMax.current = Math.max(streamMax.current, event.id);
      const from = synced.current;
      if (from === null) return; // the first page (or the catch-up after it) covers it
      if (matchesFilter(filter, event)) {
        setAdded((old) => addEvents(old ?? listRef.current, [event]));
      }
      if (event.id === from + 1) synced.current = event.id;
      else if (event.id > from + 1) void catchUp(); // a gap: some were missed
    });
    return () => {
      alive.current = false;
      unsubscribe();
    };
  }, [store, filter, catchUp]);

  // a (re)connected socket may have missed events while it was down
  const wasOpen = useRef(open);
  useEffect(() => {
    if (open && !wasOpen.current) void catchUp();
    wasOpen.current = open;
  }, [open, catchUp]);

  // a slow safety net; the socket delivers new events at once
  const refresh = useCallback(() => void catchUp(), [catchUp]);
  usePoll(refresh, TIMELINE_REFRESH_MS);

  const older = async (): Promise<void> => {
    const before = list.older;
    if (before === null) return;
    setBusy(true);
    try {
      const page = await fetchPage(timelineQuery(filter, { before }));
      setAdded((old) => addOlder(old ?? list, page));
    } catch (caught) {
      setError(asApiError(caught));
    } finally {
      setBusy(false);
    }
  };

  return (
    <>
      <ErrorText error={error ?? first.error} onRetry={first.reload} />
      {list.events.length === 0 ? (
        <p className="muted">
          {first.loading && !first.data ? t("common.loading") : t("network.timeline.empty")}
        </p>
      ) : (
        <EventList
          rows={list.events.map((e) => {
            const badge = kindBadgeKey(e.kind);
            return {
              key: e.id,
              ...e,
              kindText: badge ? t(badge) : e.kind,
              // with other buses listed, each event says whose it is
              text: filter.allBuses && e.bus ? `${eventText(e)} [${e.bus}]` : eventText(e),
            };
          })}
          caption={t("network.timeline.heading")}
          clock={formatClock}
        />
      )}
      <p className="inline small">
        <span className="muted">{t("network.timeline.shown", { shown: list.events.length })}</span>
        {list.older !== null && (
          <button type="button" disabled={busy} onClick={() => void older()}>
            {t("network.timeline.older")}
          </button>
        )}
        {busy && <Spinner label={t("network.timeline.loadingOlder")} />}
      </p>
    </>
  );
}
