import type { ReactNode } from "react";

import type { NmtStateName } from "../api/types";
import { i18n, useTranslation, type MessageKey } from "../i18n";

export const NMT_LABELS: Readonly<Record<NmtStateName, MessageKey>> = {
  operational: "nmt.state.operational",
  "pre-operational": "nmt.state.preOperational",
  stopped: "nmt.state.stopped",
  initialising: "nmt.state.initialising",
  unknown: "nmt.state.unknown",
};

/** An NMT state as the API names it ("pre-operational") in the page's language; an unknown
 * name as sent. */
export function nmtStateText(state: string): string {
  const key = NMT_LABELS[state as NmtStateName] as MessageKey | undefined;
  return key ? i18n.t(key) : state;
}

/** Colored dot for a node's NMT state; the state's name is its accessible label. */
export function NmtDot({ state, online }: { state: NmtStateName; online: boolean }): ReactNode {
  const { t } = useTranslation();
  const name = t(NMT_LABELS[state]);
  const label = online ? name : t("nmt.offline", { state: name });
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
  const { t } = useTranslation();
  const name = t(NMT_LABELS[state]);
  return (
    <span className={`badge nmt-${online ? state : "offline"}`}>
      {online ? name : t("nmt.offlineBadge", { state: name })}
    </span>
  );
}
