import type { ReactNode } from "react";

import { useTranslation } from "../i18n";

/** One line of an event table: a decoded log event or a timeline event. */
export interface EventRow {
  key: number;
  time: number;
  kind: string;
  /** The kind as shown, when it is not the raw `kind`. */
  kindText?: string;
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
  const { t } = useTranslation();
  return (
    <div className="table-scroll event-scroll">
      <table className="data-table event-table">
        <caption className="visually-hidden">{caption}</caption>
        <thead>
          <tr>
            <th scope="col">{t("events.time")}</th>
            <th scope="col">{t("events.kind")}</th>
            <th scope="col">{t("events.node")}</th>
            <th scope="col">{t("events.what")}</th>
          </tr>
        </thead>
        <tbody>
          {rows.map((row) => (
            <tr key={row.key} className={`event-row kind-${row.kind}`}>
              <td className="mono small nowrap">{clock(row.time)}</td>
              <td>
                <span className="badge event-kind">{row.kindText ?? row.kind}</span>
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
