import type { ReactNode } from "react";

import { i18n, useTranslation, type MessageKey } from "../../i18n";
import { isRecordLike, plain, rowsOf, valueText } from "./steps";

// Columns of an evidence list in a useful order; others follow in the order they come.
const FIRST = ["object", "name", "value", "expected", "now", "old", "new", "mode"];
// Carried by `object` (index, subindex) or folded into `value` (text).
const HIDDEN = new Set(["index", "subindex", "text"]);

const LIST_TITLES: Record<string, MessageKey> = {
  values: "commission.evidence.list.values",
  entries: "commission.evidence.list.entries",
  objects: "commission.evidence.list.objects",
  checked: "commission.evidence.list.checked",
  lost: "commission.evidence.list.lost",
  consumers: "commission.evidence.list.consumers",
  jogs: "commission.evidence.list.jogs",
};

// The page's words for the usual columns; any other column is named by its (server) key.
const COLUMN_TITLES: Record<string, MessageKey> = {
  object: "commission.evidence.column.object",
  name: "commission.evidence.column.name",
  value: "commission.evidence.column.value",
  expected: "commission.evidence.column.expected",
  now: "commission.evidence.column.now",
  old: "commission.evidence.column.old",
  new: "commission.evidence.column.new",
  mode: "commission.evidence.column.mode",
  source: "commission.evidence.column.source",
};

function columnsOf(rows: Record<string, unknown>[]): string[] {
  const seen = new Set<string>();
  for (const row of rows) for (const key of Object.keys(row)) if (!HIDDEN.has(key)) seen.add(key);
  const first = FIRST.filter((k) => seen.has(k));
  return [...first, ...[...seen].filter((k) => !first.includes(k))];
}

/** Own properties only: an evidence key such as "constructor" is not a catalogue entry. */
function titleOf(titles: Record<string, MessageKey>, key: string): string {
  const title = Object.hasOwn(titles, key) ? titles[key] : undefined;
  return title ? i18n.t(title) : key.replace(/_/g, " ");
}

function heading(key: string): string {
  return titleOf(LIST_TITLES, key);
}

function Cell({ row, column }: { row: Record<string, unknown>; column: string }): ReactNode {
  if (column === "value") return <td className="mono">{valueText(row)}</td>;
  const value = row[column];
  return (
    <td className={typeof value === "number" ? "num mono" : undefined}>{plain(value, column)}</td>
  );
}

/** One evidence list (values read, audit entries, lost values …) as a table. */
export function EvidenceTable({
  name,
  rows,
  label,
}: {
  name: string;
  rows: Record<string, unknown>[];
  label: string;
}): ReactNode {
  useTranslation(); // the headings follow the language
  const columns = columnsOf(rows);
  return (
    <table className={`data-table compact evidence-table evidence-${name}`} aria-label={label}>
      <caption>{heading(name)}</caption>
      <thead>
        <tr>
          {columns.map((c) => (
            <th key={c} scope="col">
              {titleOf(COLUMN_TITLES, c)}
            </th>
          ))}
        </tr>
      </thead>
      <tbody>
        {rows.map((row, i) => (
          <tr key={i}>
            {columns.map((c) => (
              <Cell key={c} row={row} column={c} />
            ))}
          </tr>
        ))}
      </tbody>
    </table>
  );
}

/** A step's evidence: lists as tables, everything else as name/value lines. */
export function EvidenceView({
  title,
  evidence,
}: {
  title: string;
  evidence: Record<string, unknown> | undefined;
}): ReactNode {
  const { t } = useTranslation();
  const entries = Object.entries(evidence ?? {});
  if (entries.length === 0) return null;
  const tables = entries.filter(([, v]) => rowsOf(v).length > 0);
  const lines = entries.filter(([, v]) => !(Array.isArray(v) && rowsOf(v).length > 0));
  return (
    <div className="evidence" aria-label={t("commission.evidence.label", { title })}>
      {tables.map(([key, value]) => (
        <EvidenceTable
          key={key}
          name={key}
          rows={rowsOf(value)}
          label={t("commission.evidence.table", { list: heading(key), step: title })}
        />
      ))}
      {lines.length > 0 && (
        <dl className="evidence-lines">
          {lines.map(([key, value]) =>
            isRecordLike(value) ? (
              Object.entries(value).map(([sub, v]) => (
                <div key={`${key}.${sub}`}>
                  <dt>
                    {key.replace(/_/g, " ")} · {sub.replace(/_/g, " ")}
                  </dt>
                  <dd>{plain(v, sub)}</dd>
                </div>
              ))
            ) : (
              <div key={key}>
                <dt>{key.replace(/_/g, " ")}</dt>
                <dd>{plain(value, key)}</dd>
              </div>
            ),
          )}
        </dl>
      )}
    </div>
  );
}
