import { useState, type ReactNode } from "react";

import { nodeFaults } from "../../api/faultsApi";
import { ErrorText } from "../../components/ErrorText";
import { useApi } from "../../lib/useApi";
import { usePoll } from "../../lib/usePoll";
import { ActiveFaultCard } from "./ActiveFaultCard";
import { DeviceHistoryCard } from "./DeviceHistoryCard";
import { FaultHistoryCard } from "./FaultHistoryTable";

export const FAULT_POLL_MS = 2000;

/** The node's active fault in words with the reset, every EMCY seen, and the drive's 1003h. */
export function FaultsPage({ node }: { node: number }): ReactNode {
  const [allBuses, setAllBuses] = useState(false);
  const faults = useApi(
    (signal) => nodeFaults(node, signal, allBuses),
    `faults-${node}-${String(allBuses)}`,
  );
  usePoll(faults.reload, FAULT_POLL_MS);
  return (
    <div className="faults-page">
      <ErrorText error={faults.data ? null : faults.error} onRetry={faults.reload} />
      <ActiveFaultCard node={node} active={faults.data?.active} onReset={faults.reload} />
      <FaultHistoryCard
        history={faults.data?.history ?? []}
        total={faults.data?.total ?? 0}
        allBuses={allBuses}
        onAllBuses={setAllBuses}
      />
      <DeviceHistoryCard node={node} />
    </div>
  );
}
