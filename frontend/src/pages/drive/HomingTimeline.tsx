import type { ReactNode } from "react";

import { useTranslation } from "../../i18n";
import { segments, TIMELINE_BITS, type Sample } from "./timeline";

const WIDTH = 300;
const LANE = 14;
const LABEL = 110;

/** Bits 10/12/13 of the statusword over the homing run, one lane each. */
export function HomingTimeline({ samples }: { samples: readonly Sample[] }): ReactNode {
  const { t } = useTranslation();
  const span = Math.max(1000, samples.at(-1)?.t ?? 0);
  const height = TIMELINE_BITS.length * LANE + 16;
  return (
    <svg
      className="homing-timeline"
      viewBox={`0 0 ${LABEL + WIDTH + 8} ${height}`}
      role="img"
      aria-label={t("drive.homing.timeline")}
    >
      {TIMELINE_BITS.map(({ bit, label }, i) => {
        const y = i * LANE + 2;
        return (
          <g key={bit} className={`ht-lane ht-bit${bit}`}>
            <text x={0} y={y + LANE - 4}>
              {t(label)}
            </text>
            <rect className="ht-off" x={LABEL} y={y + 2} width={WIDTH} height={LANE - 5} />
            {segments(samples, bit, WIDTH, span).map(([x0, x1]) => (
              <rect
                key={x0}
                className="ht-on"
                x={LABEL + x0}
                y={y + 2}
                width={Math.max(1.5, x1 - x0)}
                height={LANE - 5}
              />
            ))}
          </g>
        );
      })}
      <text x={LABEL} y={height - 2} className="ht-time">
        0 s
      </text>
      <text x={LABEL + WIDTH} y={height - 2} textAnchor="end" className="ht-time">
        {(span / 1000).toFixed(1)} s
      </text>
    </svg>
  );
}
