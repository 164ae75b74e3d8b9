import { useId, useState, type ReactNode } from "react";

import type { CompareResult } from "../../api/types";
import { useTranslation } from "../../i18n";
import { odAddress } from "../../lib/format";

interface Props {
  result: CompareResult;
  /** A file was given: rows are compared with it; otherwise with the EDS defaults. */
  withFile: boolean;
}

/** Device vs file vs EDS default, differing rows highlighted, optionally only those. */
export function CompareTable({ result, withFile }: Props): ReactNode {
  const { t } = useTranslation();
  const filterId = useId();
  const [onlyDiffs, setOnlyDiffs] = useState(true);
  const differs = (row: CompareResult["rows"][number]): boolean =>
    withFile ? row.differs_from_file : row.differs_from_default;
  const rows = onlyDiffs ? result.rows.filter(differs) : result.rows;
  const count = result.rows.filter(differs).length;
  return (
    <div className="compare">
      <div className="inline">
        <label className="check" htmlFor={filterId}>
          <input
            id={filterId}
            type="checkbox"
            checked={onlyDiffs}
            onChange={(e) => setOnlyDiffs(e.target.checked)}
          />
          {t("params.compare.onlyDifferences")}
        </label>
        <span className="muted small" role="status">
          {withFile
            ? t("params.compare.differFromFile", { differ: count, total: result.rows.length })
            : t("params.compare.differFromDefault", { differ: count, total: result.rows.length })}
        </span>
      </div>
      <div className="table-scroll compare-scroll">
        <table className="data-table">
          <thead>
            <tr>
              <th scope="col">{t("params.compare.name")}</th>
              <th scope="col">{t("params.compare.index")}</th>
              <th scope="col">{t("params.compare.device")}</th>
              <th scope="col">{t("params.compare.file")}</th>
              <th scope="col">{t("params.compare.edsDefault")}</th>
              <th scope="col">{t("params.compare.unit")}</th>
            </tr>
          </thead>
          <tbody>
            {rows.map((row) => (
              <tr
                key={`${row.index}:${row.subindex}`}
                className={differs(row) ? "differs" : undefined}
              >
                <td>{row.name}</td>
                <td className="mono">{odAddress(row.index, row.subindex)}</td>
                <td className="mono">{row.device_text || "—"}</td>
                <td className={`mono${row.differs_from_file ? " cell-differs" : ""}`}>
                  {row.file_text || "—"}
                </td>
                <td className={`mono${row.differs_from_default ? " cell-differs" : ""}`}>
                  {row.default_text || "—"}
                </td>
                <td>{row.unit || "—"}</td>
              </tr>
            ))}
          </tbody>
        </table>
        {rows.length === 0 && <p className="muted">{t("params.compare.none")}</p>}
      </div>
    </div>
  );
}
