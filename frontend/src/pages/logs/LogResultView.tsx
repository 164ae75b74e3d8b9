import type { ReactNode } from "react";

import { useTranslation } from "../../i18n";
import { exportUrl } from "./logsApi";
import { countsText, statItems } from "./logText";
import type { DecodedLog, ExportFormat, LogStats } from "./types";

const EXPORTS: { format: ExportFormat; label: string }[] = [
  { format: "csv", label: "CSV" },
  { format: "json", label: "JSON" },
  { format: "parquet", label: "Parquet" },
];

/** What the log says in plain language first, then its totals and the exports. */
export function LogResultView({
  result,
  stats,
}: {
  result: DecodedLog;
  stats: LogStats;
}): ReactNode {
  const { t } = useTranslation();
  const counts = countsText(stats.counts);
  return (
    <section className="card log-result" aria-labelledby="log-summary-heading">
      <header className="card-header">
        <h2 id="log-summary-heading">{t("logs.page.result.heading", { name: result.name })}</h2>
        <span className="spacer" />
        <span className="muted small">{t("logs.page.result.export")}</span>
        {EXPORTS.map(({ format, label }) => (
          <a key={format} className="button-link" href={exportUrl(result.id, format)} download>
            {label}
          </a>
        ))}
      </header>
      <ul className="log-summary" aria-label={t("logs.page.result.summary")}>
        {result.summary.map((line, i) => (
          <li key={i} className={i === 0 ? "lead" : undefined}>
            {line}
          </li>
        ))}
      </ul>
      <dl className="counters" aria-label={t("logs.page.result.totals")}>
        {statItems(stats).map((item) => (
          <div key={item.label} className="counter">
            <dt>{item.label}</dt>
            <dd>{item.value}</dd>
          </div>
        ))}
      </dl>
      {counts && <p className="muted small">{t("logs.page.result.byKind", { counts })}</p>}
    </section>
  );
}
