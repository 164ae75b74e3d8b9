import { useState, type ReactNode } from "react";

import { putLimits } from "../../api/driveApi";
import { ErrorText } from "../../components/ErrorText";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";
import { limitsInsideSwitches, rangeText, travelRows } from "./motionWords";
import type { DriveState, MotionLimits } from "./types";
import { checkRange, formatPct, formatRpm } from "./units";

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

/** The limits every jog, move and homing run is checked against, editable; the drive's own
 * limits they stay under; and where the axis's travel ends. */
export function LimitsCard({
  node,
  drive,
  mayCommand,
}: {
  node: number;
  drive: DriveState;
  mayCommand: boolean;
}): ReactNode {
  const limits = drive.limits;
  const own = drive.drive_limits;
  const [draft, setDraft] = useState<Record<Field, string> | null>(null);
  const operate = useMay("operate");
  const save = useAction(async (next: MotionLimits) => {
    await putLimits(node, next);
    setDraft(null);
  });
  const inside = limitsInsideSwitches(drive);
  const offer =
    inside &&
    (inside.min_position_rev !== limits.min_position_rev ||
      inside.max_position_rev !== limits.max_position_rev)
      ? inside
      : null;

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
            <dd className="num" data-testid="limit-velocity">
              {formatRpm(limits.max_velocity_rpm)}
            </dd>
            {own && (
              <dd className="muted small" title={own.velocity_source}>
                drive&apos;s own {formatRpm(own.max_velocity_rpm)}
              </dd>
            )}
          </div>
          <div>
            <dt>Max torque</dt>
            <dd className="num">{formatPct(limits.max_torque_pct)}</dd>
            {own && (
              <dd className="muted small" title={own.torque_source}>
                drive&apos;s own {formatPct(own.max_torque_pct)}
              </dd>
            )}
          </div>
        </dl>
        {own && (
          <p className="muted small" data-testid="drive-limits-source">
            The limits in force stay under the drive&apos;s own ({own.velocity_source};{" "}
            {own.torque_source}), read again while this page is open.
          </p>
        )}
        <h3 id="drive-travel-heading">Where the travel ends</h3>
        <table className="data-table" aria-labelledby="drive-travel-heading" data-testid="travel">
          <tbody>
            {travelRows(drive).map((row) => (
              <tr key={row.key} data-travel={row.key}>
                <th scope="row">
                  {row.label}
                  {row.key === "switches" && (
                    <>
                      {" "}
                      <span className="badge drive-warn">simulator</span>
                    </>
                  )}
                </th>
                <td className="num">{row.range}</td>
                <td className="muted small">
                  {row.source === "ServoDesk"
                    ? row.note
                    : `${row.source}${row.note ? ` — ${row.note}` : ""}`}
                </td>
              </tr>
            ))}
            {drive.travel && !drive.travel.software_limit && (
              <tr data-travel="no_software_limit">
                <th scope="row">Drive&apos;s software limit</th>
                <td className="num">—</td>
                <td className="muted small">no 607Dh Software position limit in its dictionary</td>
              </tr>
            )}
          </tbody>
        </table>
        {offer && (
          <div className="button-row">
            <button
              type="button"
              className="small"
              {...operate.gate("change the limits", { disabled: !mayCommand || save.busy })}
              onClick={() => void save.run(offer)}
            >
              Set ServoDesk&apos;s travel limits to{" "}
              {rangeText(offer.min_position_rev, offer.max_position_rev)}
            </button>
            <span className="muted small">
              {drive.travel?.switches ? "0.1 rev inside the limit switches" : "the drive's own"}
            </span>
            <ErrorText error={save.error} inline />
          </div>
        )}
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
