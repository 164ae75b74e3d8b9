import type { ReactNode } from "react";

import { BootUpNote } from "./BootUpNote";
import { Timeline } from "./Timeline";

/** Boot-ups, lost/back nodes, NMT, EMCYs, SDO aborts, CiA 402 states and the tool's writes, as
 * the server stored them (GET /api/events), newest first. */
export function EventsCard(): ReactNode {
  return (
    <section className="card" aria-labelledby="events-heading">
      <header className="card-header">
        <h2 id="events-heading">Timeline</h2>
        <span className="muted small">stored by the server; survives a reload</span>
      </header>
      <BootUpNote />
      <Timeline />
    </section>
  );
}
