import type { ReactNode } from "react";

import { api, call } from "../../api/client";
import type { BusState, BusStatus } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { useTranslation, type MessageKey } from "../../i18n";
import { formatBitrate, formatCount } from "../../lib/format";
import { useAction } from "../../lib/useApi";
import { useLive, useLiveStore } from "../../live/context";
import { useMay } from "../../session/context";
import { ConnectForm } from "./ConnectForm";
import { DataUsageLine } from "../../components/DataUsage";
import { LoopLag } from "./LoopLag";

const STATE_LABELS: Readonly<Record<BusState, MessageKey>> = {
  connected: "network.bus.state.connected",
  disconnected: "network.bus.state.disconnected",
  connecting: "network.bus.state.connecting",
  error: "network.bus.state.error",
};

function Counter({ label, value }: { label: string; value: number }): ReactNode {
  return (
    <div className="counter">
      <dt>{label}</dt>
      <dd className="num">{formatCount(value)}</dd>
    </div>
  );
}

function BusFacts({ bus }: { bus: BusStatus }): ReactNode {
  const { t } = useTranslation();
  return (
    <>
      <dl className="facts">
        <dt>{t("network.bus.interface")}</dt>
        <dd>{bus.interface ?? "—"}</dd>
        <dt>{t("network.bus.channel")}</dt>
        <dd className="mono">{bus.channel ?? "—"}</dd>
        <dt>{t("network.bus.bitrate")}</dt>
        <dd>{formatBitrate(bus.bitrate)}</dd>
        <dt>{t("network.bus.simulated")}</dt>
        <dd>{t(bus.simulated ? "network.bus.simulatedYes" : "network.bus.simulatedNo")}</dd>
      </dl>
      <dl className="counters" aria-label={t("network.bus.counters")}>
        <Counter label={t("network.bus.rxFrames")} value={bus.rx_frames} />
        <Counter label={t("network.bus.txFrames")} value={bus.tx_frames} />
        <Counter label={t("network.bus.errorFrames")} value={bus.error_frames} />
        <Counter label={t("network.bus.busErrors")} value={bus.bus_errors} />
        <Counter label={t("network.bus.reconnects")} value={bus.reconnects} />
      </dl>
    </>
  );
}

/** Bus state and counters (live from the WebSocket), connect / disconnect / reconnect. */
export function BusCard({ onConnected }: { onConnected: () => void }): ReactNode {
  const { t } = useTranslation();
  const bus = useLive((s) => s.bus);
  const store = useLiveStore();
  const configure = useMay("configure");
  const action = useAction(async (kind: "disconnect" | "reconnect") => {
    const status =
      kind === "disconnect"
        ? await call(api.POST("/api/bus/disconnect"))
        : await call(api.POST("/api/bus/reconnect"));
    store.apply({ type: "bus", bus: status }); // show it now, not at the next push
    if (kind === "reconnect" && status.state === "connected") onConnected();
  });
  const state = bus?.state ?? "disconnected";
  const connected = state === "connected";

  return (
    <section className="card bus-card" aria-labelledby="bus-heading">
      <header className="card-header">
        <h2 id="bus-heading">{t("network.bus.heading")}</h2>
        <span className={`badge bus-${state}`} data-testid="bus-state">
          {t(bus ? STATE_LABELS[state] : "network.bus.waiting")}
        </span>
      </header>
      <div className="bus-grid">
        <div>
          {bus?.state === "error" && bus.error && <ErrorText error={bus.error} />}
          {bus ? <BusFacts bus={bus} /> : <p className="muted">{t("network.bus.noStatus")}</p>}
          <div className="button-row">
            <button
              type="button"
              onClick={() => void action.run("disconnect")}
              {...configure.gate(t("network.gate.disconnect"), {
                disabled: action.busy || !connected,
              })}
            >
              {t("network.bus.disconnect")}
            </button>
            <button
              type="button"
              onClick={() => void action.run("reconnect")}
              {...configure.gate(t("network.gate.reconnect"), {
                disabled: action.busy || bus?.interface == null,
              })}
            >
              {t("network.bus.reconnect")}
            </button>
          </div>
          <ErrorText error={action.error} />
          <LoopLag />
          <DataUsageLine />
        </div>
        {/* Keyed so the form takes its defaults from the first status that arrives. */}
        <ConnectForm key={bus ? "ready" : "waiting"} bus={bus} onConnected={onConnected} />
      </div>
    </section>
  );
}
