import type { ReactNode } from "react";

/** One line of an event table: a decoded log event or a timeline event. */
export interface EventRow {
  key: number;
  time: number;
  kind: string;
  node: number | null;
  text: string;
}

/** Events as a table: time, kind, node, what happened. Shared by the log view and the timeline. */
export function EventList({
  rows,
  caption,
  clock,
}: {
  rows: readonly EventRow[];
  caption: string;
  clock: (time: number) => string;
}): ReactNode {
  return (
    <div className="table-scroll event-scroll">
      <table className="data-table event-table">
        <caption className="visually-hidden">{caption}</caption>
        <thead>
          <tr>
            <th scope="col">Time</th>
            <th scope="col">Kind</th>
            <th scope="col">Node</th>
            <th scope="col">What happened</th>
          </tr>
        </thead>
        <tbody>
          {rows.map((row) => (
            <tr key={row.key} className={`event-row kind-${row.kind}`}>
              <td className="mono small nowrap">{clock(row.time)}</td>
              <td>
                <span className="badge event-kind">{row.kind}</span>
              </td>
              <td className="num">{row.node ?? "—"}</td>
              <td>{row.text}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}
