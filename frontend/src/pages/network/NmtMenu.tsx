import { useRef, type ReactNode } from "react";

import type { NmtCommandName } from "../../api/types";
import { useMay } from "../../session/context";

export const NMT_COMMANDS: readonly { command: NmtCommandName; label: string }[] = [
  { command: "start", label: "Start" },
  { command: "stop", label: "Stop" },
  { command: "pre-operational", label: "Pre-op" },
  { command: "reset-node", label: "Reset node" },
  { command: "reset-communication", label: "Reset comm" },
];

interface Props {
  /** Accessible name of the menu button, e.g. "NMT for node 2". */
  label: string;
  disabled?: boolean;
  onCommand: (command: NmtCommandName) => void;
}

/** A compact dropdown of the five NMT commands (details/summary: keyboard works natively). */
export function NmtMenu({ label, disabled = false, onCommand }: Props): ReactNode {
  const details = useRef<HTMLDetailsElement>(null);
  // NMT changes what the node does on the bus: an engineer's command
  const gate = useMay("configure").gate("send NMT commands", { disabled });
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
        {NMT_COMMANDS.map(({ command, label: text }) => (
          <button
            key={command}
            type="button"
            {...gate}
            onClick={() => {
              if (details.current) details.current.open = false;
              onCommand(command);
            }}
          >
            {text}
          </button>
        ))}
      </div>
    </details>
  );
}
