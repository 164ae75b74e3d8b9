import type { ReactNode } from "react";
import { Link } from "react-router";

import { useApi } from "../lib/useApi";
import { nodeUrl } from "../nav/routes";
import { activeFaults } from "../pages/faults/faultsApi";
import { bannerText } from "../pages/faults/faultText";
import { usePoll } from "../pages/faults/usePoll";

export const BANNER_POLL_MS = 1000;

/** On every page while a node is in fault: what it is, and one click to that node's Faults tab.
 * A failed poll shows nothing (the pages report an unreachable server themselves). */
export function FaultBanner(): ReactNode {
  const active = useApi((signal) => activeFaults(signal), "faults-active");
  usePoll(active.reload, BANNER_POLL_MS);
  const faults = active.data?.faults ?? [];
  if (faults.length === 0) return null;
  return (
    <div className="fault-banner" role="alert" aria-label="Nodes in fault">
      <ul>
        {faults.map((fault) => (
          <li key={fault.node}>
            <span className="fault-banner-icon" aria-hidden="true">
              ⚠
            </span>
            <span className="fault-banner-text">{bannerText(fault)}</span>
            <Link to={nodeUrl(fault.node, "faults")}>Open node {fault.node} faults</Link>
          </li>
        ))}
      </ul>
    </div>
  );
}
