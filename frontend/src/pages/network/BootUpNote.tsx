import type { ReactNode } from "react";

import { api, call } from "../../api/client";
import { formatClock } from "../../lib/format";
import { useApi } from "../../lib/useApi";
import { useLive } from "../../live/context";

/** When this bus's timeline holds no boot-up, the drives booted before ServoDesk listened:
 * say so, with the last boot-up ServoDesk knows of (another bus, an earlier run). Read again
 * when the node list changes (a boot-up adds a node). */
export function BootUpNote(): ReactNode {
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
  return (
    <p className="muted small" role="note" aria-label="No boot-up seen">
      No boot-up on this bus since ServoDesk started listening: the drives booted before it.
      {last
        ? ` The last boot-up ServoDesk knows of: node ${String(last.node ?? "?")} at ${formatClock(
            last.time,
          )}${last.bus ? ` (${last.bus})` : ""}.`
        : ""}
    </p>
  );
}
