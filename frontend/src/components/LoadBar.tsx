import type { ReactNode } from "react";

import { formatPercent } from "../lib/format";

/** A load bar: the used share, and a mark at the threshold. */
export function LoadBar({
  percent,
  threshold,
  label,
}: {
  percent: number;
  threshold: number;
  label: string;
}): ReactNode {
  const over = percent > threshold;
  return (
    <div
      className={`load-bar${over ? " over" : ""}`}
      role="meter"
      aria-label={label}
      aria-valuemin={0}
      aria-valuemax={100}
      aria-valuenow={Math.round(percent * 10) / 10}
      aria-valuetext={formatPercent(percent)}
    >
      <div className="load-fill" style={{ width: `${Math.min(100, percent)}%` }} />
      <div className="load-threshold" style={{ left: `${Math.min(100, threshold)}%` }} />
      <span className="load-text">{formatPercent(percent)}</span>
    </div>
  );
}
