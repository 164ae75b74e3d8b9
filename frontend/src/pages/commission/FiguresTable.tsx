import type { ReactNode } from "react";

import { figureRows } from "./steps";

/** A step's figures: name, value, unit. */
export function FiguresTable({
  title,
  figures,
}: {
  title: string;
  figures: Record<string, number> | undefined;
}): ReactNode {
  const rows = figureRows(figures);
  if (rows.length === 0) return null;
  return (
    <table className="data-table compact figures-table" aria-label={`Figures of ${title}`}>
      <thead>
        <tr>
          <th scope="col">Figure</th>
          <th scope="col" className="num">
            Value
          </th>
          <th scope="col">Unit</th>
        </tr>
      </thead>
      <tbody>
        {rows.map((row) => (
          <tr key={row.name}>
            <th scope="row" title={row.name}>
              {row.label}
            </th>
            <td className="num mono">{row.value}</td>
            <td>{row.unit}</td>
          </tr>
        ))}
      </tbody>
    </table>
  );
}
