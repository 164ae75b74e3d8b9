import { useEffect, useMemo, type ReactNode } from "react";
import { Link } from "react-router";

import type { Fault } from "../api/faults";
import { activeFaults } from "../api/faultsApi";
import { i18n, useTranslation } from "../i18n";
import { faultName, isAlarmNumber } from "../lib/faultText";
import { useLive, useLiveStore } from "../live/context";
import { nodeUrl } from "../nav/paths";

/** "Node 1 in fault: alarm 4 位置超差 Following error" (the drive's own names stay as given). */
function bannerLine(fault: Fault): string {
  const code = isAlarmNumber(fault)
    ? i18n.t("faultBanner.alarm", { number: fault.code })
    : fault.code_hex;
  return i18n.t("faultBanner.text", { node: fault.node, code, name: faultName(fault) });
}

/** On every page while a node is in fault: what it is, and one click to that node's Faults tab.
 * The WebSocket's `fault` messages keep it current; one GET /api/faults/active on mount and
 * whenever the socket (re)connects or drops covers what a closed socket missed. A failed read
 * shows nothing new (the pages report an unreachable server themselves). */
export function FaultBanner(): ReactNode {
  const { t } = useTranslation();
  const store = useLiveStore();
  const open = useLive((s) => s.link.state === "open");
  const byNode = useLive((s) => s.faults);

  useEffect(() => {
    const controller = new AbortController();
    const version = store.faultVersion();
    activeFaults(controller.signal).then(
      (answer) => {
        if (!controller.signal.aborted) store.setActiveFaults(answer.faults, version);
      },
      () => undefined,
    );
    return () => controller.abort();
  }, [store, open]);

  const faults = useMemo(() => Object.values(byNode).sort((a, b) => a.node - b.node), [byNode]);
  if (faults.length === 0) return null;
  return (
    <div className="fault-banner" role="alert" aria-label={t("faultBanner.label")}>
      <ul>
        {faults.map((fault) => (
          <li key={fault.node}>
            <span className="fault-banner-icon" aria-hidden="true">
              ⚠
            </span>
            <span className="fault-banner-text">{bannerLine(fault)}</span>
            <Link to={nodeUrl(fault.node, "faults")}>
              {t("faultBanner.open", { node: fault.node })}
            </Link>
          </li>
        ))}
      </ul>
    </div>
  );
}
