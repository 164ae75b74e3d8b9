import type { ReactNode } from "react";

import { api, call } from "../../api/client";
import type { BusState, BusStatus } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { formatBitrate } from "../../lib/format";
import { useAction } from "../../lib/useApi";
import { useLive, useLiveStore } from "../../live/context";
import { useMay } from "../../session/context";
import { ConnectForm } from "./ConnectForm";
import { DataUsageLine } from "../../components/DataUsage";
import { LoopLag } from "./LoopLag";

const STATE_LABELS: Readonly<Record<BusState, string>> = {
  connected: "Connected",
  disconnected: "Disconnected",
  connecting: "Connecting…",
  error: "Error",
};

function Counter({ label, value }: { label: string; value: number }): ReactNode {
  return (
    <div className="counter">
      <dt>{label}</dt>
      <dd className="num">{value.toLocaleString("en-US")}</dd>
    </div>
  );
}

function BusFacts({ bus }: { bus: BusStatus }): ReactNode {
  return (
    <>
      <dl className="facts">
        <dt>Interface</dt>
        <dd>{bus.interface ?? "—"}</dd>
        <dt>Channel</dt>
        <dd className="mono">{bus.channel ?? "—"}</dd>
        <dt>Bitrate</dt>
        <dd>{formatBitrate(bus.bitrate)}</dd>
        <dt>Simulated</dt>
        <dd>{bus.simulated ? "yes (built-in drives)" : "no"}</dd>
      </dl>
      <dl className="counters" aria-label="Bus counters">
        <Counter label="RX frames" value={bus.rx_frames} />
        <Counter label="TX frames" value={bus.tx_frames} />
        <Counter label="Error frames" value={bus.error_frames} />
        <Counter label="Bus errors" value={bus.bus_errors} />
        <Counter label="Reconnects" value={bus.reconnects} />
      </dl>
    </>
  );
}

/** Bus state and counters (live from the WebSocket), connect / disconnect / reconnect. */
export function BusCard({ onConnected }: { onConnected: () => void }): ReactNode {
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
        <h2 id="bus-heading">CAN bus</h2>
        <span className={`badge bus-${state}`} data-testid="bus-state">
          {bus ? STATE_LABELS[state] : "Waiting for status…"}
        </span>
      </header>
      <div className="bus-grid">
        <div>
          {bus?.state === "error" && bus.error && <ErrorText error={bus.error} />}
          {bus ? <BusFacts bus={bus} /> : <p className="muted">No status from the server yet.</p>}
          <div className="button-row">
            <button
              type="button"
              onClick={() => void action.run("disconnect")}
              {...configure.gate("disconnect the bus", { disabled: action.busy || !connected })}
            >
              Disconnect
            </button>
            <button
              type="button"
              onClick={() => void action.run("reconnect")}
              {...configure.gate("reconnect the bus", {
                disabled: action.busy || bus?.interface == null,
              })}
            >
              Reconnect
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
