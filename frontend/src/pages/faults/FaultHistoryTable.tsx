import { useState, type ReactNode } from "react";

import { FaultDetails } from "./FaultDetails";
import {
  errorRegisterText,
  faultCode,
  faultName,
  formatDateTime,
  newestFirst,
  stateChange,
} from "./faultText";
import type { Fault } from "./types";

/** Faults as a table, newest first; a row opens its details below. */
export function FaultTable({
  faults,
  caption,
  states = true,
}: {
  faults: readonly Fault[];
  caption: string;
  /** Whether the rows carry the drive state before/after (ServoDesk's own history does). */
  states?: boolean;
}): ReactNode {
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
              <th scope="col">Time</th>
              <th scope="col">Code</th>
              <th scope="col">Meaning</th>
              <th scope="col">Error register</th>
              {states && <th scope="col">State before → after</th>}
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
              </tr>
            ))}
          </tbody>
        </table>
      </div>
      {shown && (
        <div className="fault-row-details" aria-label="Selected fault">
          <FaultDetails fault={shown} />
        </div>
      )}
    </>
  );
}

/** "1 EMCY stored", "120 EMCYs stored, the newest 100 shown". */
export function historyCount(total: number, shown: number): string {
  const stored = `${total} EMCY${total === 1 ? "" : "s"} stored`;
  return shown < total ? `${stored}, the newest ${shown} shown` : stored;
}

/** Every EMCY ServoDesk received from the node (resets included), newest first. */
export function FaultHistoryCard({
  history,
  total,
}: {
  history: readonly Fault[];
  total: number;
}): ReactNode {
  return (
    <section className="card" aria-labelledby="fault-history-heading">
      <header className="card-header">
        <h2 id="fault-history-heading">Fault history</h2>
        <span className="muted small">{historyCount(total, history.length)}</span>
      </header>
      {history.length === 0 ? (
        <p className="muted">No EMCY from this node yet.</p>
      ) : (
        <FaultTable faults={history} caption="Fault history" />
      )}
    </section>
  );
}
