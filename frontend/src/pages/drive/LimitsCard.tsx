import { useState, type ReactNode } from "react";

import { putLimits } from "../../api/driveApi";
import { ErrorText } from "../../components/ErrorText";
import { useTranslation, type MessageKey } from "../../i18n";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";
import { limitsInsideSwitches, rangeText, travelRows } from "./motionWords";
import type { DriveState, MotionLimits } from "./types";
import { checkRange, formatPct, formatRpm } from "./units";

type Field = "max_velocity_rpm" | "max_torque_pct" | "min_position_rev" | "max_position_rev";

const FIELDS: readonly { key: Field; label: MessageKey; optional: boolean }[] = [
  { key: "max_velocity_rpm", label: "drive.limits.maxVelocityField", optional: false },
  { key: "max_torque_pct", label: "drive.limits.maxTorqueField", optional: false },
  { key: "min_position_rev", label: "drive.limits.minPositionField", optional: true },
  { key: "max_position_rev", label: "drive.limits.maxPositionField", optional: true },
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
  const { t } = useTranslation();
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
          <h2 id="drive-limits-heading">{t("drive.limits.heading")}</h2>
          <button
            type="button"
            className="small"
            {...operate.gate(t("drive.limits.gate"), { disabled: !mayCommand })}
            onClick={() =>
              setDraft({
                max_velocity_rpm: text(limits.max_velocity_rpm),
                max_torque_pct: text(limits.max_torque_pct),
                min_position_rev: text(limits.min_position_rev),
                max_position_rev: text(limits.max_position_rev),
              })
            }
          >
            {t("drive.limits.edit")}
          </button>
        </header>
        <dl className="drive-facts">
          <div>
            <dt>{t("drive.limits.maxVelocity")}</dt>
            <dd className="num" data-testid="limit-velocity">
              {formatRpm(limits.max_velocity_rpm)}
            </dd>
            {own && (
              <dd className="muted small" title={own.velocity_source}>
                {t("drive.limits.driveOwn", { value: formatRpm(own.max_velocity_rpm) })}
              </dd>
            )}
          </div>
          <div>
            <dt>{t("drive.limits.maxTorque")}</dt>
            <dd className="num">{formatPct(limits.max_torque_pct)}</dd>
            {own && (
              <dd className="muted small" title={own.torque_source}>
                {t("drive.limits.driveOwn", { value: formatPct(own.max_torque_pct) })}
              </dd>
            )}
          </div>
        </dl>
        {own && (
          <p className="muted small" data-testid="drive-limits-source">
            {t("drive.limits.source", {
              velocity: own.velocity_source,
              torque: own.torque_source,
            })}
          </p>
        )}
        <h3 id="drive-travel-heading">{t("drive.travel.heading")}</h3>
        <table className="data-table" aria-labelledby="drive-travel-heading" data-testid="travel">
          <tbody>
            {travelRows(drive).map((row) => (
              <tr key={row.key} data-travel={row.key}>
                <th scope="row">
                  {row.label}
                  {row.key === "switches" && (
                    <>
                      {" "}
                      <span className="badge drive-warn">{t("drive.travel.simulator")}</span>
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
                <th scope="row">{t("drive.travel.softwareLimit")}</th>
                <td className="num">—</td>
                <td className="muted small">{t("drive.travel.noSoftwareLimit")}</td>
              </tr>
            )}
          </tbody>
        </table>
        {offer && (
          <div className="button-row">
            <button
              type="button"
              className="small"
              {...operate.gate(t("drive.limits.gate"), { disabled: !mayCommand || save.busy })}
              onClick={() => void save.run(offer)}
            >
              {t("drive.limits.setTravel", {
                range: rangeText(offer.min_position_rev, offer.max_position_rev),
              })}
            </button>
            <span className="muted small">
              {drive.travel?.switches
                ? t("drive.limits.insideSwitches")
                : t("drive.limits.driveOwnRange")}
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
  const rangeError =
    min !== null && max !== null && min >= max ? t("drive.limits.rangeError") : null;
  const ok = FIELDS.every((f) => checks[f.key].error === null) && rangeError === null;

  return (
    <section className="card drive-limits" aria-labelledby="drive-limits-heading">
      <header className="card-header">
        <h2 id="drive-limits-heading">{t("drive.limits.heading")}</h2>
      </header>
      <div className="drive-form">
        {FIELDS.map((f) => (
          <label key={f.key}>
            <span>{t(f.label)}</span>
            <input
              className="narrow"
              inputMode="decimal"
              placeholder={f.optional ? t("drive.limits.none") : undefined}
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
          {...operate.gate(t("drive.limits.gate"), { disabled: !ok || save.busy })}
          onClick={() =>
            void save.run({
              max_velocity_rpm: checks.max_velocity_rpm.value ?? limits.max_velocity_rpm,
              max_torque_pct: checks.max_torque_pct.value ?? limits.max_torque_pct,
              min_position_rev: min,
              max_position_rev: max,
            })
          }
        >
          {t("drive.limits.save")}
        </button>
        <button type="button" onClick={() => setDraft(null)}>
          {t("drive.limits.cancel")}
        </button>
        <ErrorText error={save.error} inline />
      </div>
    </section>
  );
}
