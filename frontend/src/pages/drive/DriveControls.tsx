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
import { useTranslation } from "../../i18n";
import { faultInWords } from "./motionWords";
import { useMay } from "../../session/context";
import { COMMANDS, stateLabel, transitionsFor, type CommandInfo } from "./stateMachine";
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
  const { t } = useTranslation();
  const operate = useMay("operate");
  const fault = drive.fault ? faultInWords(drive.fault) : null;
  const [busy, setBusy] = useState<string | null>(null);
  const [error, setError] = useState<ApiError | null>(null);
  const [blocked, setBlocked] = useState<EnableBlockedError | null>(null);
  // what the last refused request was, so "why" names it and the way out retries it; `enable`
  // tells the plain Enable apart whatever the language calls it
  const [refused, setRefused] = useState<{
    label: string;
    enable: boolean;
    retry: () => void;
  } | null>(null);
  const enableLabel = t("drive.controls.enableVerb");

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
        setRefused({ label, enable: label === enableLabel, retry: () => void run(label, work) });
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
    if (await run(t("drive.command.fault_reset"), action("fault-reset"))) {
      await run(enableLabel, action("enable"));
    }
  }

  return (
    <div className="drive-controls">
      <div className="button-row">
        <button
          type="button"
          className="primary"
          onClick={() => void run(enableLabel, action("enable"))}
          {...operate.gate(t("drive.controls.gateEnable"), {
            disabled: busy !== null || !mayCommand || enabled,
            title: t("drive.controls.enableTitle"),
          })}
        >
          {t("drive.controls.enable")}
        </button>
        <button
          type="button"
          onClick={() => void run(t("drive.controls.disableVerb"), action("disable"))}
          {...operate.gate(t("drive.controls.gateDisable"), {
            disabled: busy !== null || !mayCommand,
            title: t("drive.controls.disableTitle"),
          })}
        >
          {t("drive.controls.disable")}
        </button>
        {busy && <Spinner label={t("drive.controls.sending", { what: busy })} />}
      </div>
      {blocked && (
        <WhyBlocked
          node={node}
          blocked={blocked}
          title={
            refused && !refused.enable
              ? t("drive.controls.whyNot", { what: refused.label })
              : t("drive.controls.whyEnable")
          }
          retry={
            refused && !refused.enable
              ? t("drive.controls.sendAgain", { what: refused.label })
              : enableLabel
          }
          onRetry={refused ? refused.retry : () => void run(enableLabel, action("enable"))}
          onResetFault={mayCommand && operate.allowed ? () => void resetThenEnable() : undefined}
        />
      )}
      <ErrorText error={error} />
      <div className="transition-buttons" role="group" aria-label={t("drive.controls.commands")}>
        {COMMANDS.map((info) => {
          const label = t(info.label);
          const takes = transitionsFor(info.name, drive.state);
          // quick stop is everyone's, whatever the role or the lease
          const always = info.name === "quick_stop";
          const allowed = always || operate.allowed;
          const open = always || (mayCommand && allowed && takes.length > 0);
          const why = takes.length
            ? t("drive.controls.controlword", {
                word: info.controlword.toString(16).toUpperCase().padStart(4, "0"),
                numbers: takes.map((x) => x.number).join(t("common.listSeparator")),
              })
            : t("drive.controls.noTransition", { state: stateLabel(drive.state) });
          return (
            <button
              key={info.name}
              type="button"
              className="small"
              disabled={busy !== null || !open || takes.length === 0}
              title={allowed ? why : operate.because(t("drive.controls.gateCommands"))}
              aria-label={label}
              onClick={() => void run(label, command(info))}
            >
              {label}
              {takes.length > 0 && (
                <span className="muted"> ({takes.map((x) => x.number).join(", ")})</span>
              )}
            </button>
          );
        })}
      </div>
      {fault && (
        <div className="drive-fault" role="alert">
          <strong>
            {t("drive.controls.fault", { code: fault.code_hex })}
            {fault.name ? ` · ${fault.name}` : ""}
          </strong>
          {fault.text && <p>{fault.text}</p>}
          {fault.source && <p className="muted small">{fault.source}</p>}
        </div>
      )}
    </div>
  );
}
