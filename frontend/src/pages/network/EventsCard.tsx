import type { ReactNode } from "react";

import { formatClock } from "../../lib/format";
import { useLive } from "../../live/context";

/** Boot-ups, lost/back nodes, NMT and bus events as the WebSocket reports them, newest first. */
export function EventsCard(): ReactNode {
  const events = useLive((s) => s.events);
  return (
    <section className="card" aria-labelledby="events-heading">
      <header className="card-header">
        <h2 id="events-heading">Recent events</h2>
        <span className="muted small">{events.length} shown (last 200 kept)</span>
      </header>
      {events.length === 0 ? (
        <p className="muted">Nothing yet. Boot-ups, lost nodes and NMT changes appear here.</p>
      ) : (
        <ol className="events" aria-label="Recent events">
          {events
            .map((event, i) => ({ event, key: `${event.time}-${i}` }))
            .reverse()
            .map(({ event, key }) => (
              <li key={key} className={`event event-${event.kind}`}>
                <time className="mono small">{formatClock(event.time)}</time>
                <span className="badge">{event.kind}</span>
                {event.node !== null && <span className="event-node">node {event.node}</span>}
                <span>{event.message}</span>
              </li>
            ))}
        </ol>
      )}
    </section>
  );
}
