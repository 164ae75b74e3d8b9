import { useState, type ReactNode } from "react";

import { api, call } from "../../api/client";
import type { ScanResult } from "../../api/types";
import { useTranslation } from "../../i18n";
import { useAction } from "../../lib/useApi";
import { useLiveStore } from "../../live/context";
import { BusCard } from "./BusCard";
import { EventsCard } from "./EventsCard";
import { useLatestRecords } from "./latestRecords";
import { NodesCard } from "./NodesCard";

/** The bus, the nodes on it and what happened recently. */
export function NetworkPage(): ReactNode {
  const { t } = useTranslation();
  const store = useLiveStore();
  const [lastScan, setLastScan] = useState<ScanResult | null>(null);
  const commissioning = useLatestRecords();
  const scan = useAction(async () => {
    const result = await call(api.POST("/api/scan", { body: { sdo_sweep: true, timeout_ms: 50 } }));
    store.setInfos(result.nodes);
    setLastScan(result);
    return result;
  });
  return (
    <section className="page network-page">
      <header className="page-header">
        <h1>{t("network.title")}</h1>
      </header>
      {/* A fresh connection is scanned straight away: the next thing a user wants is the nodes. */}
      <BusCard onConnected={() => void scan.run()} />
      <NodesCard scan={scan} lastScan={lastScan} commissioning={commissioning.latest} />
      <EventsCard />
    </section>
  );
}
