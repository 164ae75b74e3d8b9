import type { ReactNode } from "react";

import { useTranslation } from "../../i18n";
import { figureRows } from "./steps";

/** A step's figures: name, value, unit. */
export function FiguresTable({
  title,
  figures,
}: {
  title: string;
  figures: Record<string, number> | undefined;
}): ReactNode {
  const { t } = useTranslation();
  const rows = figureRows(figures);
  if (rows.length === 0) return null;
  return (
    <table
      className="data-table compact figures-table"
      aria-label={t("commission.figures.label", { title })}
    >
      <thead>
        <tr>
          <th scope="col">{t("commission.figures.figure")}</th>
          <th scope="col" className="num">
            {t("commission.figures.value")}
          </th>
          <th scope="col">{t("commission.figures.unit")}</th>
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
