import type { ReactNode } from "react";

import { api, call } from "../../api/client";
import { useTranslation } from "../../i18n";
import { formatClock } from "../../lib/format";
import { useApi } from "../../lib/useApi";
import { useLive } from "../../live/context";

/** When this bus's timeline holds no boot-up, the drives booted before ServoDesk listened:
 * say so, with the last boot-up ServoDesk knows of (another bus, an earlier run). Read again
 * when the node list changes (a boot-up adds a node). */
export function BootUpNote(): ReactNode {
  const { t } = useTranslation();
  const nodes = useLive((s) => s.infos.length);
  const boots = useApi(async (signal) => {
    const mine = await call(
      api.GET("/api/events", { params: { query: { kind: "boot-up", limit: 1 } }, signal }),
    );
    if (mine.events.length > 0) return null;
    const any = await call(
      api.GET("/api/events", {
        params: { query: { kind: "boot-up", limit: 1, all_buses: true } },
        signal,
      }),
    );
    return { last: any.events[0] ?? null };
  }, `boot-up-note-${nodes}`);
  if (nodes === 0 || !boots.data) return null;
  const last = boots.data.last;
  const text = last
    ? t(last.bus ? "network.bootUp.lastOnBus" : "network.bootUp.last", {
        node: String(last.node ?? "?"),
        time: formatClock(last.time),
        bus: last.bus,
      })
    : t("network.bootUp.none");
  return (
    <p className="muted small" role="note" aria-label={t("network.bootUp.label")}>
      {text}
    </p>
  );
}
