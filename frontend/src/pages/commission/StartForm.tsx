import { useState, type SubmitEvent, type ReactNode } from "react";

import { createRecord } from "../../api/commissionApi";
import { getDrive } from "../../api/driveApi";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useAction, useApi } from "../../lib/useApi";
import { useMay } from "../../session/context";
import type { CommissioningRecord } from "./types";

const MODE_NAMES: Record<string, string> = {
  pp: "Profile position",
  pv: "Profile velocity",
  pt: "Profile torque",
  hm: "Homing",
  ip: "Interpolated position",
  csp: "Cyclic sync position",
  csv: "Cyclic sync velocity",
  cst: "Cyclic sync torque",
};

/** Checked at first: the modes a test move exercises, where the drive has them. */
const FIRST_PICK = ["pp", "pv"];

/** Start a record: the modes to commission (of those the drive supports, 6502h) and a title. */
export function StartForm({
  node,
  onStarted,
  onCancel,
}: {
  node: number;
  onStarted: (record: CommissioningRecord) => void;
  onCancel?: () => void;
}): ReactNode {
  const operate = useMay("operate");
  const drive = useApi((signal) => getDrive(node, signal), `commission-drive-${node}`);
  const supported = drive.data?.supported_modes ?? [];
  const [picked, setPicked] = useState<string[] | null>(null);
  const modes = picked ?? supported.filter((m) => FIRST_PICK.includes(m));
  const [title, setTitle] = useState("");
  const start = useAction(async () => onStarted(await createRecord(node, modes, title)));

  function toggle(mode: string, on: boolean): void {
    setPicked(on ? [...modes, mode] : modes.filter((m) => m !== mode));
  }
  function submit(event: SubmitEvent): void {
    event.preventDefault();
    void start.run();
  }

  return (
    <form className="card start-form" onSubmit={submit} aria-labelledby="start-heading">
      <header className="card-header">
        <h2 id="start-heading">Start commissioning node {node}</h2>
      </header>
      <p className="muted small">
        A record walks through nine steps, keeps the evidence of each and makes the hand-over
        report. Pick the operating modes this axis will run in.
      </p>
      {drive.error && !drive.data && <ErrorText error={drive.error} onRetry={drive.reload} />}
      {!drive.data && !drive.error && <Spinner label="Reading the supported modes" />}
      {drive.data && (
        <fieldset className="mode-picks">
          <legend>
            Modes (the drive supports{" "}
            {supported.length ? supported.join(", ").toUpperCase() : "none"})
          </legend>
          {supported.map((mode) => (
            <label key={mode} className="check">
              <input
                type="checkbox"
                checked={modes.includes(mode)}
                onChange={(e) => toggle(mode, e.target.checked)}
              />
              <span>
                <span className="mono">{mode.toUpperCase()}</span> {MODE_NAMES[mode] ?? ""}
              </span>
            </label>
          ))}
        </fieldset>
      )}
      <label className="inline">
        Title <span className="muted small">(optional)</span>
        <input
          className="wide"
          value={title}
          maxLength={200}
          placeholder={`e.g. Axis X, machine 4711`}
          onChange={(e) => setTitle(e.target.value)}
        />
      </label>
      <div className="button-row">
        <button
          type="submit"
          className="primary"
          {...operate.gate("start a commissioning record", {
            disabled: start.busy || !drive.data || modes.length === 0,
          })}
        >
          Start record
        </button>
        {onCancel && (
          <button type="button" className="link-button" onClick={onCancel}>
            Cancel
          </button>
        )}
        {drive.data && modes.length === 0 && (
          <span className="muted small">Pick at least one mode.</span>
        )}
      </div>
      <ErrorText error={start.error} />
    </form>
  );
}
