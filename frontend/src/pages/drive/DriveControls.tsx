import { useState, type ReactNode } from "react";

import type { ApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { asApiError } from "../../api/errors";
import {
  driveAction,
  EnableBlockedError,
  HeldByOtherError,
  writeControlword,
  type DriveAction,
} from "./driveApi";
import { COMMANDS, STATE_LABELS, transitionsFor, type CommandInfo } from "./stateMachine";
import type { DriveState } from "./types";
import { WhyBlocked } from "./WhyBlocked";

/** How each transition button reaches the drive: a motion route where one exists (it checks
 * the controller and explains a refusal), else the controlword alone. */
const ROUTES: Partial<Record<CommandInfo["name"], DriveAction>> = {
  enable_operation: "enable",
  quick_stop: "quick-stop",
  fault_reset: "fault-reset",
};

interface Props {
  node: number;
  drive: DriveState;
  show: (state: DriveState) => void;
  /** False while another client holds the drive: commands would be refused. */
  mayCommand: boolean;
  onHeldByOther: (error: HeldByOtherError) => void;
}

/** Enable (the whole sequence), Disable, and one button per state-machine command. */
export function DriveControls({ node, drive, show, mayCommand, onHeldByOther }: Props): ReactNode {
  const [busy, setBusy] = useState<string | null>(null);
  const [error, setError] = useState<ApiError | null>(null);
  const [blocked, setBlocked] = useState<EnableBlockedError | null>(null);

  async function run(label: string, work: () => Promise<DriveState | undefined>): Promise<void> {
    setBusy(label);
    setError(null);
    setBlocked(null);
    try {
      const state = await work();
      if (state) show(state);
    } catch (caught) {
      if (caught instanceof EnableBlockedError) {
        setBlocked(caught);
        if (caught.state) show(caught.state);
      } else if (caught instanceof HeldByOtherError) {
        onHeldByOther(caught);
      } else {
        setError(asApiError(caught));
      }
    } finally {
      setBusy(null);
    }
  }

  const action = (name: DriveAction) => () => driveAction(node, name);
  const command = (info: CommandInfo) => async (): Promise<DriveState | undefined> => {
    const route = ROUTES[info.name];
    if (route) return driveAction(node, route);
    await writeControlword(node, info.controlword);
    return undefined;
  };
  const enabled = drive.state === "operation_enabled";

  return (
    <div className="drive-controls">
      <div className="button-row">
        <button
          type="button"
          className="primary"
          disabled={busy !== null || !mayCommand || enabled}
          onClick={() => void run("enable", action("enable"))}
          title="Shutdown, switch on, enable operation: as far as the drive lets it"
        >
          Enable
        </button>
        <button
          type="button"
          disabled={busy !== null || !mayCommand}
          onClick={() => void run("disable", action("disable"))}
          title="Power stage off (shutdown to Ready to switch on)"
        >
          Disable
        </button>
        {busy && <Spinner label={`Sending ${busy}`} />}
      </div>
      {blocked && (
        <WhyBlocked
          node={node}
          blocked={blocked}
          onRetry={() => void run("enable", action("enable"))}
        />
      )}
      <ErrorText error={error} />
      <div className="transition-buttons" role="group" aria-label="State machine commands">
        {COMMANDS.map((info) => {
          const takes = transitionsFor(info.name, drive.state);
          const open = info.name === "quick_stop" || (mayCommand && takes.length > 0);
          const why = takes.length
            ? `Controlword ${info.controlword.toString(16).toUpperCase().padStart(4, "0")}h: transition ${takes.map((t) => t.number).join(", ")}`
            : `No transition from ${STATE_LABELS[drive.state]}`;
          return (
            <button
              key={info.name}
              type="button"
              className="small"
              disabled={busy !== null || !open || takes.length === 0}
              title={why}
              aria-label={info.label}
              onClick={() => void run(info.label, command(info))}
            >
              {info.label}
              {takes.length > 0 && (
                <span className="muted"> ({takes.map((t) => t.number).join(", ")})</span>
              )}
            </button>
          );
        })}
      </div>
      {drive.fault && (
        <div className="drive-fault" role="alert">
          <strong>
            Fault {drive.fault.code_hex}
            {drive.fault.name ? ` · ${drive.fault.name}` : ""}
          </strong>
          {drive.fault.text && <p>{drive.fault.text}</p>}
          {drive.fault.source && <p className="muted small">{drive.fault.source}</p>}
        </div>
      )}
    </div>
  );
}
