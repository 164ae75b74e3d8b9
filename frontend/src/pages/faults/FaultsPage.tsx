import type { ReactNode } from "react";

import { ErrorText } from "../../components/ErrorText";
import { useTranslation } from "../../i18n";
import { useLive } from "../../live/context";
import { ActiveFaultCard } from "./ActiveFaultCard";
import { DeviceHistoryCard } from "./DeviceHistoryCard";
import { FaultHistoryCard } from "./FaultHistoryTable";
import { useActiveFault, useFaultHistory } from "./useFaultHistory";

/** While the live channel is down the page cannot follow the drive: it says so (and reads the
 * faults again once the channel is back). Not during the first connection of a page load. */
function LinkDownNote(): ReactNode {
  const { t } = useTranslation();
  const down = useLive(
    (s) => s.link.state === "closed" || (s.link.state === "connecting" && s.link.attempt > 0),
  );
  if (!down) return null;
  return (
    <p className="note link-down-note" role="status">
      {t("faults.linkDown")}
    </p>
  );
}

/** The node's active fault in words with the reset, every EMCY seen, and the drive's 1003h. The
 * active fault is the live channel's (as in the banner); the history is read when it changes. */
export function FaultsPage({ node }: { node: number }): ReactNode {
  const faults = useFaultHistory(node);
  const active = useActiveFault(node, faults.data !== undefined);
  return (
    <div className="faults-page">
      <LinkDownNote />
      <ErrorText error={faults.data ? null : faults.error} onRetry={faults.reload} />
      <ActiveFaultCard node={node} active={active} />
      <FaultHistoryCard
        history={faults.data?.history ?? []}
        total={faults.data?.total ?? 0}
        allBuses={faults.allBuses}
        onAllBuses={faults.setAllBuses}
        onOlder={faults.hasOlder ? faults.older : undefined}
        loading={faults.loading && faults.data !== undefined}
      />
      <DeviceHistoryCard node={node} />
    </div>
  );
}
