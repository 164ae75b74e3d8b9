import type { ReactNode } from "react";

import type { NmtStateName } from "../api/types";

export const NMT_LABELS: Readonly<Record<NmtStateName, string>> = {
  operational: "Operational",
  "pre-operational": "Pre-operational",
  stopped: "Stopped",
  initialising: "Initialising",
  unknown: "Unknown",
};

/** Colored dot for a node's NMT state; the state's name is its accessible label. */
export function NmtDot({ state, online }: { state: NmtStateName; online: boolean }): ReactNode {
  const label = online ? NMT_LABELS[state] : `Offline (${NMT_LABELS[state]})`;
  return (
    <span
      className={`dot nmt-${online ? state : "offline"}`}
      role="img"
      aria-label={label}
      title={label}
    />
  );
}

export function NmtBadge({ state, online }: { state: NmtStateName; online: boolean }): ReactNode {
  return (
    <span className={`badge nmt-${online ? state : "offline"}`}>
      {online ? NMT_LABELS[state] : `Offline · ${NMT_LABELS[state]}`}
    </span>
  );
}
