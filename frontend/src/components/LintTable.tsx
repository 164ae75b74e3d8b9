import type { ReactNode } from "react";

import type { LintWarning } from "../api/types";

/** Import findings of an EDS/DCF/XDD file: severity, line, section, key, message. */
export function LintTable({
  warnings,
  caption,
}: {
  warnings: readonly LintWarning[];
  caption: string;
}): ReactNode {
  if (warnings.length === 0)
    return <p className="muted">No findings: the file imported cleanly.</p>;
  return (
    <div className="table-scroll lint-scroll">
      <table className="data-table">
        <caption className="visually-hidden">{caption}</caption>
        <thead>
          <tr>
            <th scope="col">Severity</th>
            <th scope="col">Line</th>
            <th scope="col">Section</th>
            <th scope="col">Key</th>
            <th scope="col">Message</th>
          </tr>
        </thead>
        <tbody>
          {warnings.map((w, i) => (
            <tr key={`${w.line ?? "-"}-${w.code}-${i}`}>
              <td>
                <span className={`badge severity-${w.severity}`}>{w.severity}</span>
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
