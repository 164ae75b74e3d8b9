import { useCallback, useEffect, useRef, useState, type ReactNode } from "react";

import { api, call } from "../../api/client";
import { asApiError, type ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { formatClock } from "../../lib/format";
import { useLive } from "../../live/context";
import { useApi } from "../../lib/useApi";
import { usePoll } from "../faults/usePoll";
import { EventList } from "./EventList";
import {
  EMPTY_TIMELINE,
  KIND_LABELS,
  addNewer,
  addOlder,
  firstPage,
  timelineQuery,
  type Timeline as TimelineList,
  type TimelineFilter,
} from "./timelineState";
import type { EventKind, TimelinePage } from "./types";

export const TIMELINE_POLL_MS = 1500;

function fetchPage(
  query: ReturnType<typeof timelineQuery>,
  signal?: AbortSignal,
): Promise<TimelinePage> {
  return call(api.GET("/api/events", { params: { query }, signal }));
}

/** What happened on the bus and in the tool, newest first: filter by node and kind, page back
 * with "older…", new events appear while the page is visible. */
export function Timeline(): ReactNode {
  const nodes = useLive((s) => s.infos.map((i) => i.node).join(","));
  const [filter, setFilter] = useState<TimelineFilter>({ node: null, kind: null });
  return (
    <>
      <div className="inline timeline-filters">
        <label htmlFor="timeline-node" className="muted small">
          Node
        </label>
        <select
          id="timeline-node"
          value={filter.node ?? ""}
          onChange={(e) =>
            setFilter({ ...filter, node: e.target.value ? Number(e.target.value) : null })
          }
        >
          <option value="">All nodes</option>
          {nodes
            .split(",")
            .filter(Boolean)
            .map((n) => (
              <option key={n} value={n}>
                Node {n}
              </option>
            ))}
        </select>
        <label htmlFor="timeline-kind" className="muted small">
          Kind
        </label>
        <select
          id="timeline-kind"
          value={filter.kind ?? ""}
          onChange={(e) =>
            setFilter({ ...filter, kind: (e.target.value || null) as EventKind | null })
          }
        >
          <option value="">All kinds</option>
          {(Object.keys(KIND_LABELS) as EventKind[]).map((kind) => (
            <option key={kind} value={kind}>
              {KIND_LABELS[kind]}
            </option>
          ))}
        </select>
      </div>
      <TimelineList key={`${filter.node}-${filter.kind}`} filter={filter} />
    </>
  );
}

/** One filter's list: the first page, then polls for newer and "older…" pages. */
function TimelineList({ filter }: { filter: TimelineFilter }): ReactNode {
  const first = useApi((signal) => fetchPage(timelineQuery(filter), signal), "timeline-first");
  const [added, setAdded] = useState<TimelineList | null>(null);
  const [error, setError] = useState<ApiError | null>(null);
  const [busy, setBusy] = useState(false);
  const list = added ?? (first.data ? firstPage(first.data) : EMPTY_TIMELINE);
  const listRef = useRef(list);
  useEffect(() => {
    listRef.current = list;
  });

  const poll = useCallback(() => {
    const current = listRef.current;
    if (current.newest === null) return;
    fetchPage(timelineQuery(filter, { since: current.newest })).then(
      (page) => {
        setAdded((old) => addNewer(old ?? current, page));
        setError(null);
      },
      (caught: unknown) => setError(asApiError(caught)),
    );
  }, [filter]);
  usePoll(poll, TIMELINE_POLL_MS);

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
          {first.loading && !first.data
            ? "Loading…"
            : "Nothing yet. Boot-ups, NMT changes, heartbeat loss, SDO aborts, EMCYs, CiA 402 states and the tool's writes appear here."}
        </p>
      ) : (
        <EventList
          rows={list.events.map((e) => ({ key: e.id, ...e, text: e.message }))}
          caption="Timeline"
          clock={formatClock}
        />
      )}
      <p className="inline small">
        <span className="muted">{list.events.length} shown</span>
        {list.older !== null && (
          <button type="button" disabled={busy} onClick={() => void older()}>
            Older…
          </button>
        )}
        {busy && <Spinner label="Loading older events" />}
      </p>
    </>
  );
}
