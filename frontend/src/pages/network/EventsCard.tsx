import type { ReactNode } from "react";

import { useTranslation } from "../../i18n";

import { BootUpNote } from "./BootUpNote";
import { Timeline } from "./Timeline";

/** Boot-ups, lost/back nodes, NMT, EMCYs, SDO aborts, CiA 402 states and the tool's writes, as
 * the server stored them (GET /api/events), newest first. */
export function EventsCard(): ReactNode {
  const { t } = useTranslation();
  return (
    <section className="card" aria-labelledby="events-heading">
      <header className="card-header">
        <h2 id="events-heading">{t("network.timeline.heading")}</h2>
        <span className="muted small">{t("network.timeline.note")}</span>
      </header>
      <BootUpNote />
      <Timeline />
    </section>
  );
}
