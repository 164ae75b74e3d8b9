import type { ReactNode } from "react";

import { api, call } from "../../api/client";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { odAddress } from "../../lib/format";
import { useAction } from "../../lib/useApi";
import { formatCobId, formatRate, isSynchronous, pdoLabel } from "./model";
import { SyncControl } from "./SyncControl";
import type { Pdo } from "./types";
import { useLiveCapture } from "./useLiveCapture";

/** After an apply: start the node, give it SYNC if the mapping needs it, and watch the PDOs
 * arrive with their rate and decoded values. */
export function LiveCheck({ node, device }: { node: number; device: readonly Pdo[] }): ReactNode {
  const live = useLiveCapture(node);
  const needsSync = device.some((p) => p.valid && isSynchronous(p.transmission_type));

  const startAll = useAction(async () => {
    await call(
      api.POST("/api/nodes/{node}/nmt", {
        params: { path: { node } },
        body: { command: "start" },
      }),
    );
    await live.start();
  });
  const rows = live.capture?.pdos ?? [];

  return (
    <section className="card" aria-labelledby="pdo-live-heading">
      <header className="card-header">
        <h2 id="pdo-live-heading">Live check</h2>
        <span className="muted small">
          Start the node and watch its PDOs: measured rate and decoded values.
        </span>
      </header>
      <div className="button-row">
        {live.running ? (
          <button type="button" onClick={() => void live.stop()}>
            Stop watching
          </button>
        ) : (
          <button
            type="button"
            className="primary"
            disabled={startAll.busy}
            onClick={() => void startAll.run()}
          >
            Start node and watch PDOs
          </button>
        )}
        {live.running && <span className="badge pdo-valid">watching</span>}
        {needsSync && <SyncControl />}
        {startAll.busy && <Spinner label="Starting" />}
      </div>
      <ErrorText error={startAll.error ?? live.error} />
      {live.capture && (
        <table className="data-table pdo-live-table" aria-label="Received PDOs">
          <thead>
            <tr>
              <th>COB-ID</th>
              <th>PDO</th>
              <th>Frames</th>
              <th>Rate</th>
              <th>Values</th>
            </tr>
          </thead>
          <tbody>
            {rows.map((row) => (
              <tr key={row.cob_id}>
                <td className="mono">{formatCobId(row.cob_id)}</td>
                <td>{pdoLabel(row)}</td>
                <td className="num">{row.frames}</td>
                <td className="num" data-testid={`rate-${row.cob_id}`}>
                  {formatRate(row.rate_hz)}
                </td>
                <td>
                  <dl className="pdo-values">
                    {row.values.map((v) => (
                      <div key={`${v.index}:${v.subindex}`}>
                        <dt title={odAddress(v.index, v.subindex)}>
                          {v.name ?? odAddress(v.index, v.subindex)}
                        </dt>
                        <dd className="num">
                          {v.value == null ? v.raw || "—" : String(v.value)}
                          {v.unit && ` ${v.unit}`}
                        </dd>
                      </div>
                    ))}
                  </dl>
                </td>
              </tr>
            ))}
            {rows.length === 0 && (
              <tr>
                <td colSpan={5} className="muted">
                  No PDO received yet.
                </td>
              </tr>
            )}
          </tbody>
        </table>
      )}
    </section>
  );
}
