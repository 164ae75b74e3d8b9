import { useId, useState, type ReactNode } from "react";

import type { CompareResult } from "../../api/types";
import { odAddress } from "../../lib/format";

interface Props {
  result: CompareResult;
  /** A file was given: rows are compared with it; otherwise with the EDS defaults. */
  withFile: boolean;
}

/** Device vs file vs EDS default, differing rows highlighted, optionally only those. */
export function CompareTable({ result, withFile }: Props): ReactNode {
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
          Only differences
        </label>
        <span className="muted small" role="status">
          {count} of {result.rows.length} entries differ from the{" "}
          {withFile ? "file" : "EDS default"}
        </span>
      </div>
      <div className="table-scroll compare-scroll">
        <table className="data-table">
          <thead>
            <tr>
              <th scope="col">Name</th>
              <th scope="col">Index</th>
              <th scope="col">Device</th>
              <th scope="col">File</th>
              <th scope="col">EDS default</th>
              <th scope="col">Unit</th>
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
        {rows.length === 0 && <p className="muted">No differences.</p>}
      </div>
    </div>
  );
}
