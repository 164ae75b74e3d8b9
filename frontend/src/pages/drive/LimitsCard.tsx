import { useState, type ReactNode } from "react";

import { ErrorText } from "../../components/ErrorText";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";
import { putLimits } from "./driveApi";
import type { MotionLimits } from "./types";
import { checkRange, formatPct, formatRev, formatRpm } from "./units";

type Field = "max_velocity_rpm" | "max_torque_pct" | "min_position_rev" | "max_position_rev";

const FIELDS: readonly { key: Field; label: string; unit: string; optional: boolean }[] = [
  { key: "max_velocity_rpm", label: "Max velocity", unit: "rpm", optional: false },
  { key: "max_torque_pct", label: "Max torque", unit: "%", optional: false },
  { key: "min_position_rev", label: "Min position", unit: "rev", optional: true },
  { key: "max_position_rev", label: "Max position", unit: "rev", optional: true },
];

function text(value: number | null | undefined): string {
  return value == null ? "" : String(value);
}

/** The limits every jog, move and homing run is checked against, editable. */
export function LimitsCard({
  node,
  limits,
  mayCommand,
}: {
  node: number;
  limits: MotionLimits;
  mayCommand: boolean;
}): ReactNode {
  const [draft, setDraft] = useState<Record<Field, string> | null>(null);
  const operate = useMay("operate");
  const save = useAction(async (next: MotionLimits) => {
    await putLimits(node, next);
    setDraft(null);
  });

  if (!draft) {
    return (
      <section className="card drive-limits" aria-labelledby="drive-limits-heading">
        <header className="card-header">
          <h2 id="drive-limits-heading">Limits in force</h2>
          <button
            type="button"
            className="small"
            {...operate.gate("change the limits", { disabled: !mayCommand })}
            onClick={() =>
              setDraft({
                max_velocity_rpm: text(limits.max_velocity_rpm),
                max_torque_pct: text(limits.max_torque_pct),
                min_position_rev: text(limits.min_position_rev),
                max_position_rev: text(limits.max_position_rev),
              })
            }
          >
            Edit
          </button>
        </header>
        <dl className="drive-facts">
          <div>
            <dt>Max velocity</dt>
            <dd className="num">{formatRpm(limits.max_velocity_rpm)}</dd>
          </div>
          <div>
            <dt>Max torque</dt>
            <dd className="num">{formatPct(limits.max_torque_pct)}</dd>
          </div>
          <div>
            <dt>Position range</dt>
            <dd className="num">
              {limits.min_position_rev == null && limits.max_position_rev == null
                ? "unlimited"
                : `${formatRev(limits.min_position_rev)} … ${formatRev(limits.max_position_rev)}`}
            </dd>
          </div>
        </dl>
      </section>
    );
  }

  const checks = Object.fromEntries(
    FIELDS.map((f) => {
      const raw = draft[f.key];
      if (f.optional && raw.trim() === "") return [f.key, { value: null, error: null }];
      return [f.key, checkRange(raw, { positive: !f.optional })];
    }),
  ) as Record<Field, { value: number | null; error: string | null }>;
  const min = checks.min_position_rev.value;
  const max = checks.max_position_rev.value;
  const rangeError = min !== null && max !== null && min >= max ? "Min must be below max" : null;
  const ok = FIELDS.every((f) => checks[f.key].error === null) && rangeError === null;

  return (
    <section className="card drive-limits" aria-labelledby="drive-limits-heading">
      <header className="card-header">
        <h2 id="drive-limits-heading">Limits in force</h2>
      </header>
      <div className="drive-form">
        {FIELDS.map((f) => (
          <label key={f.key}>
            <span>
              {f.label} ({f.unit})
            </span>
            <input
              className="narrow"
              inputMode="decimal"
              placeholder={f.optional ? "none" : undefined}
              aria-invalid={checks[f.key].error !== null}
              title={checks[f.key].error ?? undefined}
              value={draft[f.key]}
              onChange={(e) => setDraft({ ...draft, [f.key]: e.target.value })}
            />
          </label>
        ))}
      </div>
      {rangeError && <p className="error-text">{rangeError}</p>}
      <div className="button-row">
        <button
          type="button"
          className="primary"
          {...operate.gate("change the limits", { disabled: !ok || save.busy })}
          onClick={() =>
            void save.run({
              max_velocity_rpm: checks.max_velocity_rpm.value ?? limits.max_velocity_rpm,
              max_torque_pct: checks.max_torque_pct.value ?? limits.max_torque_pct,
              min_position_rev: min,
              max_position_rev: max,
            })
          }
        >
          Save limits
        </button>
        <button type="button" onClick={() => setDraft(null)}>
          Cancel
        </button>
        <ErrorText error={save.error} inline />
      </div>
    </section>
  );
}
