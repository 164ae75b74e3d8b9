import { useRef, type ReactNode } from "react";

import type { NmtCommandName } from "../../api/types";
import { useTranslation, type MessageKey } from "../../i18n";
import { useMay } from "../../session/context";

export const NMT_COMMANDS: readonly { command: NmtCommandName; labelKey: MessageKey }[] = [
  { command: "start", labelKey: "nmt.command.start" },
  { command: "stop", labelKey: "nmt.command.stop" },
  { command: "pre-operational", labelKey: "nmt.command.preOperational" },
  { command: "reset-node", labelKey: "nmt.command.resetNode" },
  { command: "reset-communication", labelKey: "nmt.command.resetCommunication" },
];

interface Props {
  /** Accessible name of the menu button, e.g. "NMT for node 2". */
  label: string;
  disabled?: boolean;
  onCommand: (command: NmtCommandName) => void;
}

/** A compact dropdown of the five NMT commands (details/summary: keyboard works natively). */
export function NmtMenu({ label, disabled = false, onCommand }: Props): ReactNode {
  const { t } = useTranslation();
  const details = useRef<HTMLDetailsElement>(null);
  // NMT changes what the node does on the bus: an engineer's command
  const gate = useMay("configure").gate(t("network.gate.nmt"), { disabled });
  return (
    <details className="menu" ref={details}>
      <summary
        aria-label={label}
        className={gate.disabled ? "disabled" : undefined}
        title={gate.title}
      >
        NMT ▾
      </summary>
      <div className="menu-items" role="group" aria-label={label}>
        {NMT_COMMANDS.map(({ command, labelKey }) => (
          <button
            key={command}
            type="button"
            {...gate}
            onClick={() => {
              if (details.current) details.current.open = false;
              onCommand(command);
            }}
          >
            {t(labelKey)}
          </button>
        ))}
      </div>
    </details>
  );
}
