import { useMemo, useState, type ReactNode } from "react";

import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { useAction, useApi } from "../../lib/useApi";
import { useMay } from "../../session/context";
import { AuditFiltersForm, NO_FILTERS } from "./AuditFiltersForm";
import { AuditTable } from "./AuditTable";
import { auditQuery, exportUrl, fetchAudit, PAGE_SIZE, type AuditQuery } from "./auditApi";
import { changeText, objectText, resultDetail, resultLabel } from "./auditText";
import type { AuditEntry, AuditFilters } from "./types";
import { UndoDialog } from "./UndoDialog";

interface OlderPages {
  /** The first page these follow; a reload of it starts the paging over. */
  base: AuditEntry[] | undefined;
  entries: AuditEntry[];
  done: boolean;
}

/** "Load older": pages before the last entry shown, appended below the first page. */
function useOlderPages(query: AuditQuery, base: AuditEntry[] | undefined) {
  const [pages, setPages] = useState<OlderPages>({ base: undefined, entries: [], done: false });
  const current = pages.base === base ? pages : { base, entries: [], done: false };
  const load = useAction(async () => {
    const last = current.entries.at(-1) ?? base?.at(-1);
    if (!last) return;
    const page = await fetchAudit(query, last.id);
    setPages({ base, entries: [...current.entries, ...page], done: page.length < PAGE_SIZE });
  });
  const more =
    base !== undefined && (current.entries.length ? !current.done : base.length >= PAGE_SIZE);
  return { entries: current.entries, more, load };
}

function UndoneNotice({ undo }: { undo: AuditEntry }): ReactNode {
  const { t } = useTranslation();
  const object = objectText(undo);
  const change = changeText(undo);
  const detail = resultDetail(undo);
  const failed = undo.result === "failed";
  const values = {
    id: undo.id,
    object: object ? t("logs.audit.notice.object", { object }) : "",
    change: change ? t("logs.audit.notice.change", { change }) : "",
    result: resultLabel(undo.result),
    detail: detail ? t("logs.audit.notice.detail", { detail }) : "",
  };
  return (
    <p className={failed ? "error-text" : "audit-notice"} role="status">
      {failed ? t("logs.audit.notice.failed", values) : t("logs.audit.notice.logged", values)}
    </p>
  );
}

/** Who changed what on which drive, when, and whether it worked; undo for value writes. */
export function AuditPage(): ReactNode {
  const { t } = useTranslation();
  const [filters, setFilters] = useState<AuditFilters>(NO_FILTERS);
  const query = useMemo(() => auditQuery(filters), [filters]);
  const first = useApi((signal) => fetchAudit(query, null, signal), JSON.stringify(query));
  const older = useOlderPages(query, first.data);
  const configure = useMay("configure");
  const [undoing, setUndoing] = useState<AuditEntry | null>(null);
  const [undone, setUndone] = useState<AuditEntry | null>(null);
  const entries = first.data ? [...first.data, ...older.entries] : [];

  return (
    <section className="page audit-page">
      <header className="page-header">
        <h1>{t("logs.audit.heading")}</h1>
        <span className="spacer" />
        <button type="button" disabled={first.loading} onClick={first.reload}>
          {t("logs.audit.refresh")}
        </button>
        <a className="button-link" href={exportUrl(query)} download>
          {t("logs.audit.export")}
        </a>
      </header>
      <section className="card">
        <AuditFiltersForm
          applied={filters}
          onApply={(next) => {
            setUndone(null);
            setFilters(next);
          }}
        />
      </section>
      {undone && <UndoneNotice undo={undone} />}
      <ErrorText error={first.error} onRetry={first.reload} />
      {!first.data ? (
        !first.error && <Spinner label={t("logs.audit.loading")} />
      ) : entries.length === 0 ? (
        <p className="muted">
          {Object.keys(query).length ? t("logs.audit.emptyFiltered") : t("logs.audit.empty")}
        </p>
      ) : (
        <section className="card">
          <AuditTable
            entries={entries}
            freshId={undone?.id ?? null}
            configure={configure}
            onUndo={setUndoing}
          />
          <div className="button-row">
            <span className="muted small">{t("logs.audit.shown", { count: entries.length })}</span>
            {older.more && (
              <button
                type="button"
                disabled={older.load.busy}
                onClick={() => void older.load.run()}
              >
                {t("logs.audit.older")}
              </button>
            )}
            {older.load.busy && <Spinner label={t("logs.audit.loadingOlder")} />}
          </div>
          <ErrorText error={older.load.error} />
        </section>
      )}
      {undoing && (
        <UndoDialog
          entry={undoing}
          onClose={() => setUndoing(null)}
          onUndone={(undo) => {
            setUndoing(null);
            setUndone(undo);
            first.reload();
          }}
        />
      )}
    </section>
  );
}
