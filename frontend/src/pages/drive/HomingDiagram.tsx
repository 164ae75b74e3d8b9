import type { ReactNode } from "react";

import { useTranslation } from "../../i18n";
import { arrowHead, describeStep, homingDrawing } from "./homingPath";
import type { HomingMethodInfo } from "./types";

/** The bend from one step's row to the next: a U-turn bulging the old way on a reversal, a
 * straight drop on a change of speed. */
function joinPath(
  join: { x: number; y0: number; y1: number; reversal: boolean },
  direction: "positive" | "negative",
): string {
  const { x, y0, y1 } = join;
  if (!join.reversal) return `M${x} ${y0} L${x} ${y1}`;
  const bulge = x + (direction === "positive" ? -12 : 12);
  return `M${x} ${y0} C${bulge} ${y0}, ${bulge} ${y1}, ${x} ${y1}`;
}

/** A method's path after the manual's figures: the switches on the axis, one arrow per step
 * (bold fast, thin dashed slow), the reversals as bends, the home position marked. */
export function HomingDiagram({ method }: { method: HomingMethodInfo }): ReactNode {
  const { t } = useTranslation();
  const d = homingDrawing(method.path);
  const words = method.path.length
    ? method.path.map(describeStep).join(t("drive.homing.then"))
    : t("drive.homing.noMotion");
  return (
    <svg
      className="homing-diagram"
      viewBox={`0 0 ${d.width} ${d.height}`}
      role="img"
      aria-label={t("drive.homing.path", { method: method.method, words })}
      data-testid={`homing-diagram-${method.method}`}
    >
      {d.switches.map((s) => (
        <g key={s.name} className={`hd-switch hd-${s.name}`}>
          <rect x={s.x0} y={d.axisY - 9} width={s.x1 - s.x0} height={9} />
          <text x={(s.x0 + s.x1) / 2} y={d.axisY + 20} textAnchor="middle">
            {s.label}
          </text>
        </g>
      ))}
      <line className="hd-axis" x1={8} x2={d.width - 8} y1={d.axisY} y2={d.axisY} />
      {d.arrows.map((a) => (
        <g key={a.index} className={`hd-step hd-${a.speed}`}>
          <title>{describeStep(method.path[a.index] ?? a)}</title>
          {a.join && <path className="hd-join" d={joinPath(a.join, a.direction)} />}
          <line x1={a.x0} x2={a.x1} y1={a.y} y2={a.y} />
          <polygon points={arrowHead(a.x1, a.y, a.direction)} />
          <text x={(a.x0 + a.x1) / 2} y={a.y - 4} textAnchor="middle" className="hd-speed">
            {a.speed === "fast" ? "H" : "L"}
          </text>
        </g>
      ))}
      <circle className="hd-start" cx={d.start} cy={d.arrows[0]?.y ?? d.axisY - 14} r={3.5} />
      <g className="hd-home">
        <line x1={d.end} x2={d.end} y1={d.axisY - 12} y2={d.axisY + 4} />
        <polygon
          points={`${d.end},${d.axisY} ${d.end - 4},${d.axisY - 7} ${d.end + 4},${d.axisY - 7}`}
        />
        <text
          x={d.end + (d.homeAnchor === "start" ? 4 : d.homeAnchor === "end" ? -4 : 0)}
          y={d.axisY + 20}
          textAnchor={d.homeAnchor}
        >
          {t("drive.homing.home")}
        </text>
      </g>
    </svg>
  );
}
