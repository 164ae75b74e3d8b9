import type { ReactNode } from "react";

import { isSynchronous, pdoLabel } from "./model";
import { SyncControl } from "./SyncControl";
import type { Pdo, Validation } from "./types";

interface Props {
  draft: readonly Pdo[];
  validation: Validation | null;
  /** The user says SYNC comes from the machine's controller (sync_source "external"). */
  external: boolean;
  onExternal: (external: boolean) => void;
  /** SYNC was started here: a checked draft is checked again. */
  onSyncStarted?: () => void;
}

/** Where a synchronous draft gets its SYNC: ServoDesk's producer, another producer heard on
 * the bus, or the machine's controller (a PLC not connected on the bench). Without any of
 * them the server warns; the user acknowledges it here or starts SYNC. */
export function SyncChoice({
  draft,
  validation,
  external,
  onExternal,
  onSyncStarted,
}: Props): ReactNode {
  const synchronous = draft.filter((p) => p.valid && isSynchronous(p.transmission_type));
  if (synchronous.length === 0) return null;
  const labels = synchronous.map(pdoLabel).join(", ");
  const sync = validation?.sync;
  if (sync?.heard) {
    const period = sync.heard_period_us ? ` every ${sync.heard_period_us / 1000} ms` : "";
    return (
      <p className="small pdo-sync-choice" role="status">
        SYNC heard on the bus from another producer{period}: {labels} get it.
      </p>
    );
  }
  const warned = (validation?.warnings ?? []).length > 0;
  return (
    <div className="pdo-sync-choice" role="group" aria-label="SYNC for the synchronous PDOs">
      {warned && (
        <p className="warning" role="alert">
          {synchronous.length === 1 ? `${labels} is` : `${labels} are`} synchronous but no SYNC is
          produced or heard on the bus: {synchronous.length === 1 ? "it acts" : "they act"} only
          once SYNC comes.{" "}
          {external
            ? "It can be written: SYNC comes from the machine's controller."
            : "Start the SYNC producer, or say that SYNC comes from the machine's controller, to write it."}
        </p>
      )}
      <span className="inline">
        <label className="small">
          <input
            type="checkbox"
            checked={external}
            onChange={(e) => onExternal(e.target.checked)}
          />{" "}
          SYNC comes from the machine&apos;s controller (PLC)
        </label>
        <SyncControl onStarted={onSyncStarted} />
      </span>
    </div>
  );
}
