import { useEffect, type ReactNode } from "react";

import { api, call } from "../../api/client";
import type { components } from "../../api/schema";
import { i18n, useTranslation } from "../../i18n";
import { useApi } from "../../lib/useApi";

type Lag = components["schemas"]["LoopLag"];

/** The real-time lane's targets (docs/architecture.md): beyond them a stop may be late. */
export const LAG_P99_MS = 20;
export const LAG_MAX_MS = 100;
const POLL_MS = 5000;

/** Words for the server's event-loop lag over the last minute (pure, table-tested). */
export function lagWords(lag: Lag): { text: string; busy: boolean } {
  const figures = i18n.t("network.loopLag.figures", {
    p50: lag.p50_ms.toFixed(1),
    p99: lag.p99_ms.toFixed(1),
    max: lag.max_ms.toFixed(0),
  });
  const busy = lag.p99_ms > LAG_P99_MS || lag.max_ms > LAG_MAX_MS;
  return {
    text: busy ? i18n.t("network.loopLag.busy", { figures }) : figures,
    busy,
  };
}

/** How late the server's event loop ran over the last minute (GET /api/health, every 5 s). */
export function LoopLag(): ReactNode {
  const { t } = useTranslation();
  const health = useApi((signal) => call(api.GET("/api/health", { signal })), "health");
  const { reload } = health;
  useEffect(() => {
    const timer = setInterval(reload, POLL_MS);
    return () => clearInterval(timer);
  }, [reload]);
  const lag = health.data?.loop;
  if (!lag || lag.samples === 0) return null;
  const words = lagWords(lag);
  return (
    <p
      className={words.busy ? "small loop-lag busy" : "small muted loop-lag"}
      data-testid="loop-lag"
      title={t("network.loopLag.title", { window: lag.window_s.toFixed(0), count: lag.samples })}
    >
      {t("network.loopLag.line", { text: words.text })}
    </p>
  );
}
