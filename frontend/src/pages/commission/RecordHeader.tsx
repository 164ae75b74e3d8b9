import type { ReactNode } from "react";

import { reportUrl } from "../../api/commissionApi";
import { RecordChip } from "../../components/StatusChip";
import { currentLanguage, i18n, useTranslation, type MessageKey } from "../../i18n";
import { hex, profileLabel } from "../../lib/format";
import { useMay } from "../../session/context";
import { localDateTime, progress } from "./steps";
import type { CommissioningRecord, RecordStatus } from "./types";

/** The record's status in words: the shell's, as its badge says it. */
const RECORD_STATUS: Record<RecordStatus, MessageKey> = {
  in_progress: "status.record.inProgress",
  done: "status.record.done",
  failed: "status.record.failed",
};

function created(record: CommissioningRecord): string {
  return localDateTime(record.created);
}

/** "#3 Axis X — 27/11/2026, 10:02 (In progress)" for the record chooser. */
export function recordLabel(record: CommissioningRecord): string {
  return i18n.t("commission.record.option", {
    id: record.id,
    title: record.title || i18n.t("commission.record.untitled"),
    created: created(record),
    status: i18n.t(RECORD_STATUS[record.status]),
  });
}

/** The record's overall status, the drive it was made for, the chooser and the report links. */
export function RecordHeader({
  record,
  records,
  onChoose,
  onNew,
}: {
  record: CommissioningRecord;
  records: readonly CommissioningRecord[];
  onChoose: (id: number) => void;
  onNew: () => void;
}): ReactNode {
  const { t } = useTranslation();
  const language = currentLanguage(); // the report in the page's language
  const operate = useMay("operate");
  const { closed, total } = progress(record);
  const id = record.identity;
  return (
    <section className="card record-header" aria-labelledby="record-heading">
      <header className="card-header">
        <h2 id="record-heading">
          {record.title
            ? t("commission.record.headingTitled", { id: record.id, title: record.title })
            : t("commission.record.heading", { id: record.id })}
        </h2>
        <RecordChip status={record.status} />
        <span className="muted" aria-label={t("commission.record.progressLabel")}>
          {t("commission.record.progress", { closed, total })}
        </span>
        <span className="spacer" />
        <button type="button" {...operate.gate(t("commission.start.gate"))} onClick={onNew}>
          {t("commission.record.new")}
        </button>
      </header>
      <dl className="record-facts">
        <div>
          <dt>{t("commission.record.drive")}</dt>
          <dd>
            {id.name ?? "—"} <span className="muted">({profileLabel(id)})</span>
          </dd>
        </div>
        <div>
          <dt>{t("commission.record.identity")}</dt>
          <dd className="mono small">
            {t("commission.record.identityLine", {
              vendor: hex(id.vendor_id),
              product: hex(id.product_code),
              revision: hex(id.revision),
              serial: hex(id.serial),
            })}
          </dd>
        </div>
        <div>
          <dt>{t("commission.record.modes")}</dt>
          <dd>{record.modes.map((m) => m.toUpperCase()).join(" · ") || "—"}</dd>
        </div>
        <div>
          <dt>{t("commission.record.started")}</dt>
          <dd>{created(record)}</dd>
        </div>
      </dl>
      <div className="button-row">
        {records.length > 1 && (
          <label className="inline">
            {t("commission.record.choose")}
            <select
              value={record.id}
              aria-label={t("commission.record.chooseLabel")}
              onChange={(e) => onChoose(Number(e.target.value))}
            >
              {records.map((r) => (
                <option key={r.id} value={r.id}>
                  {recordLabel(r)}
                </option>
              ))}
            </select>
          </label>
        )}
        <span className="spacer" />
        <span className="group-label">{t("commission.record.report")}</span>
        <a
          className="button-link"
          href={reportUrl(record.id, "html", language)}
          target="_blank"
          rel="noopener"
        >
          {t("commission.record.reportHtml")}
        </a>
        <a
          className="button-link"
          href={reportUrl(record.id, "pdf", language)}
          target="_blank"
          rel="noopener"
        >
          PDF
        </a>
        <a className="button-link" href={reportUrl(record.id, "zip", language)} download>
          {t("commission.record.bundle")}
        </a>
      </div>
    </section>
  );
}
