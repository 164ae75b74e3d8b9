import { useState, type ReactNode } from "react";

import { ErrorText } from "../../components/ErrorText";
import { EventList } from "../../components/EventList";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { useApi } from "../../lib/useApi";
import { logEvents } from "./logsApi";
import { FIRST_PAGE, currentStart, logClock, pageBack, pageForward, pageLabel } from "./logText";
import type { DecodedLog, LogEventPage } from "./types";

/** The server's page size (the decode answer carries the first page). */
export const LOG_PAGE_SIZE = 500;

/** The decoded events of one log, a page at a time. */
export function LogEventsCard({
  result,
  total,
}: {
  result: DecodedLog;
  total: number | null;
}): ReactNode {
  const { t } = useTranslation();
  const [pager, setPager] = useState(FIRST_PAGE);
  // SDO reads repeated at a steady period: mostly ServoDesk's own Drive page polling
  const [hidePolling, setHidePolling] = useState(false);
  const start = currentStart(pager);
  const page = useApi(
    (signal) =>
      start === 0 && !hidePolling
        ? Promise.resolve<LogEventPage>({ events: result.events, next: result.next })
        : logEvents(result.id, start, LOG_PAGE_SIZE, signal, hidePolling),
    `log-events-${result.id}-${start}-${hidePolling ? "hide" : "all"}`,
  );
  const events = page.data?.events ?? [];
  const next = page.data?.next ?? null;
  return (
    <section className="card" aria-labelledby="log-events-heading">
      <header className="card-header">
        <h2 id="log-events-heading">{t("logs.page.events.heading")}</h2>
        <span className="muted small">{pageLabel(events, total)}</span>
        <span className="spacer" />
        <label className="inline small">
          <input
            type="checkbox"
            checked={hidePolling}
            onChange={(e) => {
              setHidePolling(e.target.checked);
              setPager(FIRST_PAGE); // the pages differ: start over
            }}
          />
          {t("logs.page.events.hidePolling")}
        </label>
        <button
          type="button"
          disabled={pager.starts.length < 2 || page.loading}
          onClick={() => setPager(pageBack)}
        >
          {t("logs.page.events.previous")}
        </button>
        <button
          type="button"
          disabled={next === null || page.loading}
          onClick={() => next !== null && setPager((p) => pageForward(p, next))}
        >
          {t("logs.page.events.next")}
        </button>
        {page.loading && <Spinner label={t("logs.page.events.loading")} />}
      </header>
      <ErrorText error={page.error} onRetry={page.reload} />
      {events.length > 0 ? (
        <EventList
          rows={events.map((e) => ({
            key: e.seq,
            time: e.time,
            kind: e.kind,
            node: e.node,
            text: e.text,
          }))}
          caption={t("logs.page.events.heading")}
          clock={logClock}
        />
      ) : (
        !page.loading && <p className="muted">{t("logs.page.events.empty")}</p>
      )}
    </section>
  );
}
