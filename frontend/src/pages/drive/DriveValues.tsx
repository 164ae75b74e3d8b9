import type { ReactNode } from "react";

import { useTranslation, type MessageKey } from "../../i18n";
import { Lamp } from "./StatusLamps";
import type { DriveState } from "./types";
import { formatInc, formatPct, formatRev, formatRpm, modeLabel } from "./units";

const INPUTS: readonly { key: string; label: MessageKey; tone: "warn" | "info" }[] = [
  { key: "negative_limit", label: "drive.input.negative_limit", tone: "warn" },
  { key: "home_switch", label: "drive.input.home_switch", tone: "info" },
  { key: "positive_limit", label: "drive.input.positive_limit", tone: "warn" },
];

/** Where a value came from: the drive's own TPDO frames, or an SDO read (in turn). */
function Source({ drive, name }: { drive: DriveState; name: string }): ReactNode {
  const { t } = useTranslation();
  const source = drive.sources?.[name];
  if (!source) return null;
  const frames = source.startsWith("TPDO");
  const written = source === "written";
  return (
    <span
      className={frames ? "badge source source-pdo" : "badge source source-sdo"}
      data-testid={`source-${name}`}
      title={
        frames
          ? t("drive.values.sourcePdo", { source })
          : written
            ? t("drive.values.sourceWritten")
            : t("drive.values.sourceSdo")
      }
    >
      {source}
    </span>
  );
}

/** A hint when values are polled by SDO: mapping them in a TPDO shows them live. */
function SourceHint({ drive }: { drive: DriveState }): ReactNode {
  const { t } = useTranslation();
  const polled = ["position", "velocity", "torque", "following_error"].filter(
    (name) => drive.sources?.[name] === "SDO",
  );
  if (polled.length === 0) return null;
  return (
    <p className="muted small" data-testid="source-hint">
      {t("drive.values.sourceHint")}
    </p>
  );
}

/** Mode 6060h beside its display 6061h, the actual values and the input lamps. */
export function DriveValues({ drive }: { drive: DriveState }): ReactNode {
  const { t } = useTranslation();
  const mismatch = drive.mode !== null && drive.mode !== drive.mode_display;
  return (
    <section className="card drive-values" aria-labelledby="drive-values-heading">
      <header className="card-header">
        <h2 id="drive-values-heading">{t("drive.values.heading")}</h2>
        {drive.target_reached && (
          <span className="badge drive-ok">{t("drive.values.targetReached")}</span>
        )}
        {drive.homed === true && <span className="badge drive-ok">{t("drive.values.homed")}</span>}
        {drive.homed === false && <span className="badge">{t("drive.values.notHomed")}</span>}
      </header>
      <dl className="drive-facts">
        <div>
          <dt title={t("drive.values.modeTitle")}>{t("drive.values.mode")}</dt>
          <dd data-testid="mode">{modeLabel(drive.mode)}</dd>
        </div>
        <div>
          <dt title={t("drive.values.displayTitle")}>
            {t("drive.values.display")} <Source drive={drive} name="mode_display" />
          </dt>
          <dd className={mismatch ? "drive-warn-text" : undefined} data-testid="mode-display">
            {modeLabel(drive.mode_display)}
            {mismatch && t("drive.values.notTaken")}
          </dd>
        </div>
        <div>
          <dt title={t("drive.values.supportedTitle")}>{t("drive.values.supported")}</dt>
          <dd>{drive.supported_modes.map((m) => m.toUpperCase()).join(" · ") || "—"}</dd>
        </div>
        <div>
          <dt title={t("drive.values.positionTitle")}>
            {t("drive.values.position")} <Source drive={drive} name="position" />
          </dt>
          <dd className="num" data-testid="position">
            {formatRev(drive.position_rev)}
            <span className="muted small block">{formatInc(drive.position_inc)}</span>
          </dd>
        </div>
        <div>
          <dt title={t("drive.values.velocityTitle")}>
            {t("drive.values.velocity")} <Source drive={drive} name="velocity" />
          </dt>
          <dd className="num" data-testid="velocity">
            {formatRpm(drive.velocity_rpm)}
          </dd>
        </div>
        <div>
          <dt title={t("drive.values.torqueTitle")}>
            {t("drive.values.torque")} <Source drive={drive} name="torque" />
          </dt>
          <dd className="num">{formatPct(drive.torque_pct)}</dd>
        </div>
        <div>
          <dt title={t("drive.values.followingTitle")}>
            {t("drive.values.following")} <Source drive={drive} name="following_error" />
          </dt>
          <dd className="num">{formatInc(drive.following_error_inc)}</dd>
        </div>
        <div>
          <dt title={t("drive.values.resolutionTitle")}>{t("drive.values.resolution")}</dt>
          <dd className="num">
            {t("drive.values.perRev", { value: formatInc(drive.counts_per_rev) })}
            {drive.gear_ratio && (
              <span className="muted small block">
                {t("drive.values.gear", {
                  motor: drive.gear_ratio[0],
                  shaft: drive.gear_ratio[1],
                })}
              </span>
            )}
          </dd>
        </div>
      </dl>
      <SourceHint drive={drive} />
      <h3>{t("drive.values.inputsHeading")}</h3>
      <ul className="lamps inputs" aria-label={t("drive.values.inputs")}>
        {INPUTS.map((input) => (
          <Lamp
            key={input.key}
            on={drive.inputs[input.key] === true}
            tone={input.tone}
            label={t(input.label)}
          />
        ))}
      </ul>
    </section>
  );
}
