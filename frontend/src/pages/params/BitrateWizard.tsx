import { useId, useState, type ReactNode } from "react";

import { api, call } from "../../api/client";
import type { BitrateChangeResult, BitrateOptions } from "../../api/types";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { formatBitrate } from "../../lib/format";
import { useAction } from "../../lib/useApi";
import { useLive, useLiveStore } from "../../live/context";
import { useMay } from "../../session/context";

/** Change the node's CAN bitrate, then offer to reconnect the tool at the new rate. Only the
 * rates the node's profile can set are offered; a drive that sets its bitrate elsewhere says
 * so instead of offering a change that cannot succeed. */
export function BitrateWizard({ node }: { node: number }): ReactNode {
  const selectId = useId();
  const store = useLiveStore();
  const bus = useLive((s) => s.bus);
  const [open, setOpen] = useState(false);
  const [bitrate, setBitrate] = useState(String(bus?.bitrate ?? 500_000));
  const [result, setResult] = useState<BitrateChangeResult | null>(null);
  const [options, setOptions] = useState<BitrateOptions | null>(null);
  const fetchOptions = useAction(async () => {
    const answer = await call(
      api.GET("/api/nodes/{node}/bitrates", { params: { path: { node } } }),
    );
    setOptions(answer);
    const current = answer.current ?? bus?.bitrate;
    const other = answer.supported.find((rate) => rate !== current);
    if (other !== undefined) setBitrate(String(other));
  });
  const change = useAction(async () => {
    setResult(
      await call(
        api.POST("/api/nodes/{node}/change-bitrate", {
          params: { path: { node } },
          body: { bitrate: Number(bitrate), confirm: true },
        }),
      ),
    );
  });
  const reconnect = useAction(async (rate: number) => {
    const status = await call(
      api.POST("/api/bus/connect", {
        body: {
          interface: bus?.interface ?? null,
          channel: bus?.channel ?? null,
          bitrate: rate,
          options: {},
          simulated: bus?.simulated ?? false,
        },
      }),
    );
    store.apply({ type: "bus", bus: status });
    if (status.state === "connected") setOpen(false);
  });

  const configure = useMay("configure");

  function close(): void {
    setOpen(false);
    setResult(null);
    setOptions(null);
  }

  const title = `Change the bitrate of node ${node}`;
  return (
    <>
      <button
        type="button"
        onClick={() => {
          setOpen(true);
          void fetchOptions.run();
        }}
        {...configure.gate("change the bitrate")}
      >
        Change bitrate…
      </button>
      {open && !result && options && !options.settable && (
        <Dialog
          title={title}
          onClose={close}
          actions={
            <button type="button" onClick={close}>
              Close
            </button>
          }
        >
          <p role="status">{options.note}</p>
          <p>
            Set the same bitrate on the drive itself, then reconnect the bus at it on the Network
            page.
          </p>
        </Dialog>
      )}
      {open && !result && !options && (
        <Dialog
          title={title}
          onClose={close}
          actions={
            <button type="button" onClick={close}>
              Cancel
            </button>
          }
        >
          {fetchOptions.busy && <Spinner label="Reading the supported bitrates" />}
          <ErrorText error={fetchOptions.error} onRetry={() => void fetchOptions.run()} />
        </Dialog>
      )}
      {open && !result && options?.settable && (
        <Dialog
          title={title}
          onClose={close}
          actions={
            <>
              <button type="button" onClick={close}>
                Cancel
              </button>
              <button
                type="button"
                className="primary"
                disabled={change.busy}
                onClick={() => void change.run()}
              >
                Change bitrate
              </button>
              {change.busy && <Spinner label="Changing bitrate" />}
            </>
          }
        >
          <label htmlFor={selectId}>New bitrate</label>
          <select id={selectId} value={bitrate} onChange={(e) => setBitrate(e.target.value)}>
            {options.supported.map((rate) => (
              <option key={rate} value={String(rate)}>
                {formatBitrate(rate)}
                {rate === options.current ? " (now)" : ""}
              </option>
            ))}
          </select>
          <p className="muted small">{options.note}</p>
          <p>
            The server will write the drive's bitrate parameter, store the parameters and reset the
            node.
          </p>
          <p>
            From then on node {node} talks only at {formatBitrate(Number(bitrate))}: it disappears
            from this bus
            {bus?.bitrate ? ` (now ${formatBitrate(bus.bitrate)})` : ""} until the bus is
            reconnected at the new bitrate. Every other node on the bus must be changed too.
          </p>
          <ErrorText error={change.error} />
        </Dialog>
      )}
      {open && result && (
        <Dialog
          title="Bitrate changed"
          onClose={close}
          actions={
            <>
              <button type="button" onClick={close}>
                Later
              </button>
              <button
                type="button"
                className="primary"
                disabled={reconnect.busy}
                onClick={() => void reconnect.run(result.bitrate)}
              >
                Reconnect the bus at {formatBitrate(result.bitrate)}
              </button>
              {reconnect.busy && <Spinner label="Reconnecting" />}
            </>
          }
        >
          <ol className="steps">
            {result.steps.map((step, i) => (
              <li key={i}>{step}</li>
            ))}
          </ol>
          <p>
            The node now uses {formatBitrate(result.bitrate)}. Reconnect the bus at that bitrate to
            talk to it again (the Network page's Connect form does the same).
          </p>
          <ErrorText error={reconnect.error} />
        </Dialog>
      )}
    </>
  );
}
