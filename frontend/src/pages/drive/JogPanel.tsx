import { useState, type ReactNode } from "react";

import { useTranslation } from "../../i18n";
import { HoldJog } from "./HoldJog";
import { IpStreamPanel } from "./IpStreamPanel";
import { PpJog } from "./PpJog";
import type { DriveState } from "./types";
import { modeLabel } from "./units";

const JOG_MODES = ["pp", "pv", "pt", "ip"] as const;
type JogTab = (typeof JOG_MODES)[number];

/** One tab per supported mode that can move the axis by hand (homing has its own card). */
export function JogPanel({
  node,
  drive,
  show,
  mayCommand,
}: {
  node: number;
  drive: DriveState;
  show: (state: DriveState) => void;
  mayCommand: boolean;
}): ReactNode {
  const { t } = useTranslation();
  const modes = JOG_MODES.filter((m) => drive.supported_modes.includes(m));
  const [picked, setPicked] = useState<JogTab | null>(null);
  const tab = picked && modes.includes(picked) ? picked : (modes[0] ?? null);
  const props = { node, drive, mayCommand };
  return (
    <section className="card drive-jog" aria-labelledby="drive-jog-heading">
      <header className="card-header">
        <h2 id="drive-jog-heading">{t("drive.jog.heading")}</h2>
        <div className="tabs mode-tabs" role="tablist" aria-label={t("drive.jog.modes")}>
          {modes.map((m) => (
            <button
              key={m}
              type="button"
              role="tab"
              aria-selected={m === tab}
              className={m === tab ? "tab active" : "tab"}
              onClick={() => setPicked(m)}
            >
              {modeLabel(m)}
            </button>
          ))}
        </div>
      </header>
      {tab === null && <p className="muted">{t("drive.jog.noMode")}</p>}
      {tab === "pp" && <PpJog {...props} show={show} />}
      {tab === "pv" && <HoldJog {...props} mode="pv" />}
      {tab === "pt" && <HoldJog {...props} mode="pt" />}
      {tab === "ip" && <IpStreamPanel {...props} show={show} />}
    </section>
  );
}
