// The Network page's view of commissioning: each node's latest record and its status.
import { useEffect } from "react";

import type { CommissioningRecord, RecordStatus } from "../../api/commission";
import { listRecords } from "../../api/commissionApi";
import { useApi } from "../../lib/useApi";

export interface LatestRecord {
  id: number;
  status: RecordStatus;
  title: string;
}

/** Node → its newest record, from a newest-first list of every node's records. */
export function latestByNode(
  records: readonly CommissioningRecord[],
): ReadonlyMap<number, LatestRecord> {
  const latest = new Map<number, LatestRecord>();
  for (const r of records) {
    if (!latest.has(r.node)) latest.set(r.node, { id: r.id, status: r.status, title: r.title });
  }
  return latest;
}

/** Loaded once per page load, and again when the tab comes back into view (a record may have
 * changed in another tab meanwhile); never polled. */
export function useLatestRecords(): {
  latest: ReadonlyMap<number, LatestRecord> | null;
  error: ReturnType<typeof useApi>["error"];
} {
  const records = useApi((signal) => listRecords(null, signal), "commission-latest");
  const { reload } = records;
  useEffect(() => {
    const onVisibility = (): void => {
      if (document.visibilityState === "visible") reload();
    };
    document.addEventListener("visibilitychange", onVisibility);
    return () => document.removeEventListener("visibilitychange", onVisibility);
  }, [reload]);
  return { latest: records.data ? latestByNode(records.data) : null, error: records.error };
}
