import { useState, type ReactNode } from "react";

import {
  driveAction,
  driveCommand,
  EnableBlockedError,
  HeldByOtherError,
  type DriveAction,
} from "../../api/driveApi";
import type { ApiError } from "../../api/errors";
import { asApiError } from "../../api/errors";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useMay } from "../../session/context";
import { COMMANDS, STATE_LABELS, transitionsFor, type CommandInfo } from "./stateMachine";
import type { DriveState } from "./types";
import { WhyBlocked } from "./WhyBlocked";

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
  const operate = useMay("operate");
  const [busy, setBusy] = useState<string | null>(null);
  const [error, setError] = useState<ApiError | null>(null);
  const [blocked, setBlocked] = useState<EnableBlockedError | null>(null);
  // what the last refused request was, so "why" names it and the way out retries it
  const [refused, setRefused] = useState<{ label: string; retry: () => void } | null>(null);

  /** One request; true when it was answered with the drive state. */
  async function run(label: string, work: () => Promise<DriveState>): Promise<boolean> {
    setBusy(label);
    setError(null);
    setBlocked(null);
    try {
      show(await work());
      return true;
    } catch (caught) {
      if (caught instanceof EnableBlockedError) {
        setBlocked(caught);
        setRefused({ label, retry: () => void run(label, work) });
        if (caught.state) show(caught.state);
      } else if (caught instanceof HeldByOtherError) {
        onHeldByOther(caught);
      } else {
        setError(asApiError(caught));
      }
      return false;
    } finally {
      setBusy(null);
    }
  }

  const action = (name: DriveAction) => () => driveAction(node, name);
  /** Every transition button: the server writes the command's controlword behind the lease
   * and explains a transition that does not happen. */
  const command = (info: CommandInfo) => () => driveCommand(node, info.name);
  const enabled = drive.state === "operation_enabled";
  /** Two acts, each its own request (and audit entry): the fault reset, then the enable. */
  async function resetThenEnable(): Promise<void> {
    if (await run("Fault reset", action("fault-reset"))) await run("enable", action("enable"));
  }

  return (
    <div className="drive-controls">
      <div className="button-row">
        <button
          type="button"
          className="primary"
          onClick={() => void run("enable", action("enable"))}
          {...operate.gate("enable the drive", {
            disabled: busy !== null || !mayCommand || enabled,
            title: "Shutdown, switch on, enable operation: as far as the drive lets it",
          })}
        >
          Enable
        </button>
        <button
          type="button"
          onClick={() => void run("disable", action("disable"))}
          {...operate.gate("disable the drive", {
            disabled: busy !== null || !mayCommand,
            title: "Power stage off (shutdown to Ready to switch on)",
          })}
        >
          Disable
        </button>
        {busy && <Spinner label={`Sending ${busy}`} />}
      </div>
      {blocked && (
        <WhyBlocked
          node={node}
          blocked={blocked}
          title={
            refused && refused.label !== "enable"
              ? `Why didn't ${refused.label} happen?`
              : "Why won't it enable?"
          }
          retry={refused && refused.label !== "enable" ? `send ${refused.label} again` : "enable"}
          onRetry={refused ? refused.retry : () => void run("enable", action("enable"))}
          onResetFault={mayCommand && operate.allowed ? () => void resetThenEnable() : undefined}
        />
      )}
      <ErrorText error={error} />
      <div className="transition-buttons" role="group" aria-label="State machine commands">
        {COMMANDS.map((info) => {
          const takes = transitionsFor(info.name, drive.state);
          // quick stop is everyone's, whatever the role or the lease
          const always = info.name === "quick_stop";
          const allowed = always || operate.allowed;
          const open = always || (mayCommand && allowed && takes.length > 0);
          const why = takes.length
            ? `Controlword ${info.controlword.toString(16).toUpperCase().padStart(4, "0")}h: transition ${takes.map((t) => t.number).join(", ")}`
            : `No transition from ${STATE_LABELS[drive.state]}`;
          return (
            <button
              key={info.name}
              type="button"
              className="small"
              disabled={busy !== null || !open || takes.length === 0}
              title={allowed ? why : operate.because("send drive commands")}
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
