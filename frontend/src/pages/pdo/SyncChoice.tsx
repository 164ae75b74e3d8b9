import type { ReactNode } from "react";

import { useTranslation } from "../../i18n";
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
  const { t } = useTranslation();
  const synchronous = draft.filter((p) => p.valid && isSynchronous(p.transmission_type));
  if (synchronous.length === 0) return null;
  const labels = synchronous.map(pdoLabel).join(t("common.listSeparator"));
  const sync = validation?.sync;
  if (sync?.heard) {
    return (
      <p className="small pdo-sync-choice" role="status">
        {sync.heard_period_us
          ? t("pdo.sync.heardEvery", { ms: sync.heard_period_us / 1000, pdos: labels })
          : t("pdo.sync.heard", { pdos: labels })}
      </p>
    );
  }
  const warned = (validation?.warnings ?? []).length > 0;
  return (
    <div className="pdo-sync-choice" role="group" aria-label={t("pdo.sync.group")}>
      {warned && (
        <p className="warning" role="alert">
          {t("pdo.sync.notProduced", { count: synchronous.length, pdos: labels })}{" "}
          {external ? t("pdo.sync.canWrite") : t("pdo.sync.startOrSay")}
        </p>
      )}
      <span className="inline">
        <label className="small">
          <input
            type="checkbox"
            checked={external}
            onChange={(e) => onExternal(e.target.checked)}
          />{" "}
          {t("pdo.sync.external")}
        </label>
        <SyncControl onStarted={onSyncStarted} />
      </span>
    </div>
  );
}
