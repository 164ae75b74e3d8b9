import type { ReactNode } from "react";

import { useTranslation } from "../../i18n";
import { sparklinePath } from "./sparkline";

const WIDTH = 120;
const HEIGHT = 28;

/** The last values of one signal as a small line (no axes: the viewer has the plot). */
export function Sparkline({
  values,
  label,
}: {
  values: readonly number[];
  label: string;
}): ReactNode {
  const { t } = useTranslation();
  const path = sparklinePath(values, WIDTH, HEIGHT);
  return (
    <svg
      className="scope-spark"
      width={WIDTH}
      height={HEIGHT}
      viewBox={`0 0 ${WIDTH} ${HEIGHT}`}
      role="img"
      aria-label={t("scope.capture.sparkline", { label, count: values.length })}
    >
      <path d={path} fill="none" stroke="currentColor" strokeWidth={1.5} strokeLinejoin="round" />
    </svg>
  );
}
