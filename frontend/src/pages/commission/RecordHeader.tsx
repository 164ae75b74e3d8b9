import type { ReactNode } from "react";

import { reportUrl } from "../../api/commissionApi";
import { RecordChip, RECORD_STATUS_TEXT } from "../../components/StatusChip";
import { hex } from "../../lib/format";
import { useMay } from "../../session/context";
import { progress } from "./steps";
import type { CommissioningRecord } from "./types";

function created(record: CommissioningRecord): string {
  return new Date(record.created * 1000).toLocaleString();
}

/** "#3 Axis X — 27/11/2026, 10:02 (In progress)" for the record chooser. */
export function recordLabel(record: CommissioningRecord): string {
  return `#${record.id} ${record.title || "untitled"} — ${created(record)} (${RECORD_STATUS_TEXT[record.status]})`;
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
  const operate = useMay("operate");
  const { closed, total } = progress(record);
  const id = record.identity;
  return (
    <section className="card record-header" aria-labelledby="record-heading">
      <header className="card-header">
        <h2 id="record-heading">
          Record #{record.id}
          {record.title ? `: ${record.title}` : ""}
        </h2>
        <RecordChip status={record.status} />
        <span className="muted" aria-label="Progress">
          {closed} of {total} steps done or skipped
        </span>
        <span className="spacer" />
        <button type="button" {...operate.gate("start a commissioning record")} onClick={onNew}>
          New record…
        </button>
      </header>
      <dl className="record-facts">
        <div>
          <dt>Drive</dt>
          <dd>
            {id.name ?? "—"} <span className="muted">({id.profile_label})</span>
          </dd>
        </div>
        <div>
          <dt>Identity (1018h)</dt>
          <dd className="mono small">
            vendor {hex(id.vendor_id)} · product {hex(id.product_code)} · rev {hex(id.revision)} ·
            SN {hex(id.serial)}
          </dd>
        </div>
        <div>
          <dt>Modes</dt>
          <dd>{record.modes.map((m) => m.toUpperCase()).join(" · ") || "—"}</dd>
        </div>
        <div>
          <dt>Started</dt>
          <dd>{created(record)}</dd>
        </div>
      </dl>
      <div className="button-row">
        {records.length > 1 && (
          <label className="inline">
            Record
            <select
              value={record.id}
              aria-label="Choose a record"
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
        <span className="group-label">Hand-over report</span>
        <a
          className="button-link"
          href={reportUrl(record.id, "html")}
          target="_blank"
          rel="noopener"
        >
          Report (HTML)
        </a>
        <a
          className="button-link"
          href={reportUrl(record.id, "pdf")}
          target="_blank"
          rel="noopener"
        >
          PDF
        </a>
        <a className="button-link" href={reportUrl(record.id, "zip")} download>
          Bundle (zip)
        </a>
      </div>
    </section>
  );
}
