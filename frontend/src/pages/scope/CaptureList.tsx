import { useId, useState, type ReactNode } from "react";

import type { ApiError } from "../../api/errors";
import { DataUsageLine } from "../../components/DataUsage";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { odAddress } from "../../lib/format";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";
import { formatBytes, formatDateTime, isActive, triggerText } from "./model";
import { exportUrl, stopOrDeleteCapture } from "./scopeApi";
import type { Capture, ExportFormat, ExportLayout } from "./types";

const EXPORTS: { format: ExportFormat; layout?: ExportLayout; label: string; title: string }[] = [
  { format: "csv", label: "CSV", title: "one row per sample" },
  {
    format: "csv",
    layout: "wide",
    label: "Wide CSV",
    title: "for spreadsheets: one row per time stamp, a column per signal",
  },
  { format: "parquet", label: "Parquet", title: "Apache Parquet table" },
  { format: "mf4", label: "MF4", title: "ASAM MDF 4, one channel per signal" },
  { format: "rrd", label: ".rrd", title: "the rerun recording, for rerun's desktop viewer" },
];

function signalList(capture: Capture): string {
  return capture.signals
    .map((s) => `node ${s.node} ${odAddress(s.index, s.subindex)} ${s.name}`)
    .join("\n");
}

/** Read the usage again when a capture comes, goes or finishes (its size is then known). */
function usageVersion(captures: readonly Capture[] | undefined): number {
  return (captures ?? []).reduce((sum, c) => sum + c.id * 31 + c.size_bytes, 0);
}

/** The captures kept, newest first: open one in the viewer, export it, delete it. */
export function CaptureList({
  captures,
  loading,
  error,
  onReload,
  onOpen,
  onDeleted,
}: {
  captures: readonly Capture[] | undefined;
  loading: boolean;
  error: ApiError | null;
  onReload: () => void;
  onOpen: (capture: Capture) => void;
  onDeleted: (id: number) => void;
}): ReactNode {
  const id = useId();
  const operate = useMay("operate");
  const [asking, setAsking] = useState<Capture | null>(null);
  const remove = useAction(async (capture: Capture) => {
    await stopOrDeleteCapture(capture.id);
    setAsking(null);
    onDeleted(capture.id);
  });
  return (
    <section className="card scope-list" aria-labelledby={`${id}-h`}>
      <header className="card-header">
        <h2 id={`${id}-h`}>Captures</h2>
        {captures && <span className="muted small">{captures.length} kept</span>}
        {loading && <Spinner label="Loading the captures" />}
        <span className="spacer" />
        <button type="button" className="small" onClick={onReload}>
          Refresh
        </button>
      </header>
      <DataUsageLine kind="captures" version={usageVersion(captures)} />
      <ErrorText error={error} onRetry={onReload} />
      {captures?.length === 0 && <p className="muted">No captures yet.</p>}
      {captures && captures.length > 0 && (
        <div className="table-scroll scope-list-scroll">
          <table className="data-table scope-list-table" aria-label="Captures">
            <thead>
              <tr>
                <th className="num">#</th>
                <th>Name</th>
                <th>State</th>
                <th>Nodes</th>
                <th className="num">Signals</th>
                <th>Trigger</th>
                <th>Time</th>
                <th className="num">Samples</th>
                <th className="num">Size</th>
                <th>Open · export · delete</th>
              </tr>
            </thead>
            <tbody>
              {captures.map((capture) => {
                const active = isActive(capture);
                return (
                  <tr key={capture.id} data-capture={capture.id}>
                    <td className="num">{capture.id}</td>
                    <td className="scope-wrap">
                      {capture.name ?? <span className="muted">—</span>}
                    </td>
                    <td>
                      <span className={`badge scope-state scope-state-${capture.state}`}>
                        {capture.state}
                      </span>
                      {capture.error && (
                        <span className="block error-text small">{capture.error}</span>
                      )}
                    </td>
                    <td>{capture.nodes.join(", ")}</td>
                    <td className="num" title={signalList(capture)}>
                      {capture.signals.length}
                    </td>
                    <td className="small scope-wrap">{triggerText(capture.trigger)}</td>
                    <td className="small num scope-wrap">{formatDateTime(capture.created)}</td>
                    <td className="num">{capture.samples.toLocaleString("en-US")}</td>
                    <td className="num">{active ? "—" : formatBytes(capture.size_bytes)}</td>
                    <td className="scope-wrap scope-actions-cell">
                      <span className="scope-actions">
                        <button
                          type="button"
                          className="small"
                          disabled={active}
                          title={active ? "The live view shows it while it records" : undefined}
                          aria-label={`Open capture ${capture.id} in the viewer`}
                          onClick={() => onOpen(capture)}
                        >
                          Open in viewer
                        </button>
                        {EXPORTS.map(({ format, layout, label, title }) =>
                          active ? (
                            <span key={label} className="muted small">
                              {label}
                            </span>
                          ) : (
                            <a
                              key={label}
                              className="button-link small"
                              href={exportUrl(capture.id, format, layout)}
                              download
                              title={`Export ${title}`}
                              aria-label={`Export capture ${capture.id} as ${label}`}
                            >
                              {label}
                            </a>
                          ),
                        )}
                        <button
                          type="button"
                          className="small danger"
                          {...operate.gate("delete a capture", {
                            disabled: active,
                            title: active ? "Stop it first" : undefined,
                          })}
                          aria-label={`Delete capture ${capture.id}`}
                          onClick={() => {
                            remove.clearError();
                            setAsking(capture);
                          }}
                        >
                          Delete
                        </button>
                      </span>
                    </td>
                  </tr>
                );
              })}
            </tbody>
          </table>
        </div>
      )}
      {asking && (
        <Dialog
          title={`Delete capture ${asking.id}?`}
          onClose={() => setAsking(null)}
          actions={
            <>
              <button type="button" onClick={() => setAsking(null)}>
                Cancel
              </button>
              <button
                type="button"
                className="danger"
                disabled={remove.busy}
                onClick={() => void remove.run(asking)}
              >
                Delete capture {asking.id}
              </button>
            </>
          }
        >
          <p>
            Capture {asking.id}
            {asking.name ? ` (${asking.name})` : ""} of {formatDateTime(asking.created)} and its
            files (.rrd and samples) are deleted. Exports already downloaded stay.
          </p>
          <ErrorText error={remove.error} />
        </Dialog>
      )}
    </section>
  );
}
