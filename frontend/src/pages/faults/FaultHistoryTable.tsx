import { useState, type ReactNode } from "react";

import { Spinner } from "../../components/Spinner";
import { i18n, useTranslation } from "../../i18n";
import {
  errorRegisterText,
  faultCode,
  faultName,
  formatDateTime,
  newestFirst,
  stateChange,
} from "../../lib/faultText";
import { FaultDetails } from "./FaultDetails";
import type { Fault } from "./types";

/** Faults as a table, newest first; a row opens its details below. */
export function FaultTable({
  faults,
  caption,
  states = true,
  buses = false,
}: {
  faults: readonly Fault[];
  caption: string;
  /** Whether the rows carry the drive state before/after (ServoDesk's own history does). */
  states?: boolean;
  /** Whether each row names the bus it came from (other buses' faults are listed too). */
  buses?: boolean;
}): ReactNode {
  const { t } = useTranslation();
  const [open, setOpen] = useState<number | null>(null);
  const rows = newestFirst(faults);
  const shown = open === null ? undefined : rows[open];
  return (
    <>
      <div className="table-scroll fault-table-scroll">
        <table className="data-table fault-table">
          <caption className="visually-hidden">{caption}</caption>
          <thead>
            <tr>
              <th scope="col">{t("faults.history.time")}</th>
              <th scope="col">{t("faults.history.code")}</th>
              <th scope="col">{t("faults.history.meaning")}</th>
              <th scope="col">{t("faults.history.errorRegister")}</th>
              {states && <th scope="col">{t("faults.history.states")}</th>}
              {buses && <th scope="col">{t("faults.history.bus")}</th>}
            </tr>
          </thead>
          <tbody>
            {rows.map((fault, i) => (
              <tr
                key={`${fault.time}-${fault.code}-${i}`}
                className={`clickable${open === i ? " selected" : ""}`}
                aria-selected={open === i}
                tabIndex={0}
                onClick={() => setOpen(open === i ? null : i)}
                onKeyDown={(event) => {
                  if (event.key === "Enter" || event.key === " ") {
                    event.preventDefault();
                    setOpen(open === i ? null : i);
                  }
                }}
              >
                <td className="mono small nowrap">{formatDateTime(fault.time)}</td>
                <td className="mono">{faultCode(fault)}</td>
                <td>{faultName(fault)}</td>
                <td className="small">{errorRegisterText(fault.error_register)}</td>
                {states && <td className="small">{stateChange(fault)}</td>}
                {buses && <td className="small mono">{fault.bus ?? "—"}</td>}
              </tr>
            ))}
          </tbody>
        </table>
      </div>
      {shown && (
        <div className="fault-row-details" aria-label={t("faults.history.selected")}>
          <FaultDetails fault={shown} />
        </div>
      )}
    </>
  );
}

/** "1 EMCY stored", "120 EMCYs stored, the newest 100 shown". */
export function historyCount(total: number, shown: number): string {
  const stored = i18n.t("faults.history.stored", { count: total });
  return shown < total ? i18n.t("faults.history.storedShown", { stored, shown }) : stored;
}

/** Every EMCY ServoDesk received from the node on this bus (resets included), newest first;
 * with `allBuses`, also those stored from other buses, each naming its bus; "Older…" loads
 * more when fewer are shown than stored. */
export function FaultHistoryCard({
  history,
  total,
  allBuses = false,
  onAllBuses,
  onOlder,
  loading = false,
}: {
  history: readonly Fault[];
  total: number;
  allBuses?: boolean;
  onAllBuses?: (all: boolean) => void;
  onOlder?: () => void;
  /** A read of the list is under way (the list shown is the previous one). */
  loading?: boolean;
}): ReactNode {
  const { t } = useTranslation();
  return (
    <section className="card" aria-labelledby="fault-history-heading">
      <header className="card-header">
        <h2 id="fault-history-heading">{t("faults.history.heading")}</h2>
        <span className="muted small">{historyCount(total, history.length)}</span>
        {onAllBuses && (
          <label className="check small" title={t("faults.history.otherBusesTitle")}>
            <input
              type="checkbox"
              checked={allBuses}
              onChange={(e) => onAllBuses(e.target.checked)}
            />
            {t("faults.history.otherBuses")}
          </label>
        )}
      </header>
      {history.length === 0 ? (
        <p className="muted">
          {allBuses ? t("faults.history.emptyAllBuses") : t("faults.history.empty")}
        </p>
      ) : (
        <FaultTable faults={history} caption={t("faults.history.heading")} buses={allBuses} />
      )}
      {onOlder && (
        <p className="inline small">
          <button type="button" disabled={loading} onClick={onOlder}>
            {t("faults.history.older")}
          </button>
          {loading && <Spinner label={t("faults.history.reading")} />}
        </p>
      )}
    </section>
  );
}
