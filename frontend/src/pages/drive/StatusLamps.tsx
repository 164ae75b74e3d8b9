import type { ReactNode } from "react";

import { useTranslation } from "../../i18n";
import { statusLamps, wordHex } from "./statusBits";
import type { DriveState } from "./types";

/** One lamp with its name; lit in its tone when on. */
export function Lamp({
  on,
  tone,
  label,
  detail,
}: {
  on: boolean;
  tone: "ok" | "bad" | "warn" | "info";
  label: string;
  detail?: string;
}): ReactNode {
  const { t } = useTranslation();
  return (
    <li
      className={on ? `lamp on ${tone}` : "lamp"}
      aria-label={on ? t("drive.status.lampOn", { label }) : t("drive.status.lampOff", { label })}
    >
      <span className="lamp-light" aria-hidden="true" />
      {detail && <span className="lamp-bit mono">{detail}</span>}
      <span className="lamp-name">{label}</span>
    </li>
  );
}

/** Statusword 6041h decoded bit by bit, and the controlword 6040h last sent. */
export function StatusLamps({ drive }: { drive: DriveState }): ReactNode {
  const { t } = useTranslation();
  const lamps = statusLamps(drive.statusword, drive.mode_display ?? drive.mode, drive.status_bits);
  return (
    <section className="card drive-status" aria-labelledby="drive-status-heading">
      <header className="card-header">
        <h2 id="drive-status-heading">{t("drive.status.heading")}</h2>
        <span className="mono" title={t("drive.status.statuswordTitle")} data-testid="statusword">
          6041h = {wordHex(drive.statusword)}
        </span>
        <span className="mono muted small" title={t("drive.status.controlwordTitle")}>
          6040h = {wordHex(drive.controlword)}
        </span>
      </header>
      <ul className="lamps" aria-label={t("drive.status.bits")}>
        {lamps.map((lamp) => (
          <Lamp
            key={lamp.bit}
            on={lamp.on}
            tone={lamp.tone}
            label={lamp.name}
            detail={String(lamp.bit)}
          />
        ))}
      </ul>
    </section>
  );
}
