import type { ReactNode } from "react";

import { Lamp } from "./StatusLamps";
import type { DriveState } from "./types";
import { formatInc, formatPct, formatRev, formatRpm, modeLabel } from "./units";

const INPUTS: readonly { key: string; label: string; tone: "warn" | "info" }[] = [
  { key: "negative_limit", label: "Negative limit (N-OT)", tone: "warn" },
  { key: "home_switch", label: "Home switch (HW)", tone: "info" },
  { key: "positive_limit", label: "Positive limit (P-OT)", tone: "warn" },
];

/** Where a value came from: the drive's own TPDO frames, or an SDO read (in turn). */
function Source({ drive, name }: { drive: DriveState; name: string }): ReactNode {
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
          ? `From the drive's ${source} frames: current with every frame`
          : written
            ? "As ServoDesk last wrote it, confirmed by the drive"
            : "Read by SDO, in turn with the other values no TPDO carries (at most 2 reads per 100 ms)"
      }
    >
      {source}
    </span>
  );
}

/** A hint when values are polled by SDO: mapping them in a TPDO shows them live. */
function SourceHint({ drive }: { drive: DriveState }): ReactNode {
  const polled = ["position", "velocity", "torque", "following_error"].filter(
    (name) => drive.sources?.[name] === "SDO",
  );
  if (polled.length === 0) return null;
  return (
    <p className="muted small" data-testid="source-hint">
      Values marked SDO are read in turn, a few times a second. Map them in a TPDO (PDOs page →
      recommended mapping for your modes) to see them with every frame.
    </p>
  );
}

/** Mode 6060h beside its display 6061h, the actual values and the input lamps. */
export function DriveValues({ drive }: { drive: DriveState }): ReactNode {
  const mismatch = drive.mode !== null && drive.mode !== drive.mode_display;
  return (
    <section className="card drive-values" aria-labelledby="drive-values-heading">
      <header className="card-header">
        <h2 id="drive-values-heading">Actual values</h2>
        {drive.target_reached && <span className="badge drive-ok">target reached</span>}
        {drive.homed === true && <span className="badge drive-ok">homed</span>}
        {drive.homed === false && <span className="badge">not homed</span>}
      </header>
      <dl className="drive-facts">
        <div>
          <dt title="6060h Modes of operation">Mode 6060h</dt>
          <dd data-testid="mode">{modeLabel(drive.mode)}</dd>
        </div>
        <div>
          <dt title="6061h Modes of operation display">
            Display 6061h <Source drive={drive} name="mode_display" />
          </dt>
          <dd className={mismatch ? "drive-warn-text" : undefined} data-testid="mode-display">
            {modeLabel(drive.mode_display)}
            {mismatch && " (not yet taken)"}
          </dd>
        </div>
        <div>
          <dt title="6502h Supported drive modes">Supported</dt>
          <dd>{drive.supported_modes.map((m) => m.toUpperCase()).join(" · ") || "—"}</dd>
        </div>
        <div>
          <dt title="6064h Position actual value">
            Position <Source drive={drive} name="position" />
          </dt>
          <dd className="num" data-testid="position">
            {formatRev(drive.position_rev)}
            <span className="muted small block">{formatInc(drive.position_inc)}</span>
          </dd>
        </div>
        <div>
          <dt title="606Ch Velocity actual value">
            Velocity <Source drive={drive} name="velocity" />
          </dt>
          <dd className="num" data-testid="velocity">
            {formatRpm(drive.velocity_rpm)}
          </dd>
        </div>
        <div>
          <dt title="6077h Torque actual value">
            Torque <Source drive={drive} name="torque" />
          </dt>
          <dd className="num">{formatPct(drive.torque_pct)}</dd>
        </div>
        <div>
          <dt title="60F4h Following error actual value">
            Following error <Source drive={drive} name="following_error" />
          </dt>
          <dd className="num">{formatInc(drive.following_error_inc)}</dd>
        </div>
        <div>
          <dt title="Encoder increments per motor revolution">Resolution</dt>
          <dd className="num">
            {formatInc(drive.counts_per_rev)}/rev
            {drive.gear_ratio && (
              <span className="muted small block">
                gear {drive.gear_ratio[0]} : {drive.gear_ratio[1]}
              </span>
            )}
          </dd>
        </div>
      </dl>
      <SourceHint drive={drive} />
      <h3>Digital inputs 60FDh</h3>
      <ul className="lamps inputs" aria-label="Digital inputs">
        {INPUTS.map((input) => (
          <Lamp
            key={input.key}
            on={drive.inputs[input.key] === true}
            tone={input.tone}
            label={input.label}
          />
        ))}
      </ul>
    </section>
  );
}
