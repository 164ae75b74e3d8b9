import type { ReactNode } from "react";

import type { LintWarning } from "../api/types";
import { type MessageKey, useTranslation } from "../i18n";

const SEVERITY: Readonly<Record<LintWarning["severity"], MessageKey>> = {
  info: "common.lint.severityName.info",
  warning: "common.lint.severityName.warning",
  error: "common.lint.severityName.error",
};

/** Import findings of an EDS/DCF/XDD file: severity, line, section, key, message. */
export function LintTable({
  warnings,
  caption,
}: {
  warnings: readonly LintWarning[];
  caption: string;
}): ReactNode {
  const { t } = useTranslation();
  if (warnings.length === 0) return <p className="muted">{t("common.lint.noFindings")}</p>;
  return (
    <div className="table-scroll lint-scroll">
      <table className="data-table">
        <caption className="visually-hidden">{caption}</caption>
        <thead>
          <tr>
            <th scope="col">{t("common.lint.severity")}</th>
            <th scope="col">{t("common.lint.line")}</th>
            <th scope="col">{t("common.lint.section")}</th>
            <th scope="col">{t("common.lint.key")}</th>
            <th scope="col">{t("common.lint.message")}</th>
          </tr>
        </thead>
        <tbody>
          {warnings.map((w, i) => (
            <tr key={`${w.line ?? "-"}-${w.code}-${i}`}>
              <td>
                <span className={`badge severity-${w.severity}`}>{t(SEVERITY[w.severity])}</span>
              </td>
              <td className="num">{w.line ?? "—"}</td>
              <td className="mono">{w.section ?? "—"}</td>
              <td className="mono">{w.key ?? "—"}</td>
              <td>{w.message}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}
