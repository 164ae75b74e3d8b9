import { useId, useState, type ReactNode } from "react";

import type { ApiError } from "../../api/errors";
import { DataUsageLine } from "../../components/DataUsage";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { currentLocale, i18n, useTranslation, type MessageKey } from "../../i18n";
import { odAddress } from "../../lib/format";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";
import { formatBytes, formatDateTime, isActive, STATE_WORD, triggerText } from "./model";
import { exportUrl, stopOrDeleteCapture } from "./scopeApi";
import type { Capture, ExportFormat, ExportLayout } from "./types";

// `label` is a format's name (the same in every language) or a key when it needs words
const EXPORTS: {
  format: ExportFormat;
  layout?: ExportLayout;
  label: string;
  labelKey?: MessageKey;
  title: MessageKey;
}[] = [
  { format: "csv", label: "CSV", title: "scope.list.export.csv" },
  {
    format: "csv",
    layout: "wide",
    label: "Wide CSV",
    labelKey: "scope.list.export.wideCsvLabel",
    title: "scope.list.export.wideCsv",
  },
  { format: "parquet", label: "Parquet", title: "scope.list.export.parquet" },
  { format: "mf4", label: "MF4", title: "scope.list.export.mf4" },
  { format: "rrd", label: ".rrd", title: "scope.list.export.rrd" },
];

function signalList(capture: Capture): string {
  return capture.signals
    .map((s) =>
      i18n.t("scope.list.signalLine", {
        node: s.node,
        address: odAddress(s.index, s.subindex),
        name: s.name,
      }),
    )
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
  const { t } = useTranslation();
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
        <h2 id={`${id}-h`}>{t("scope.list.heading")}</h2>
        {captures && (
          <span className="muted small">{t("scope.list.kept", { count: captures.length })}</span>
        )}
        {loading && <Spinner label={t("scope.list.loading")} />}
        <span className="spacer" />
        <button type="button" className="small" onClick={onReload}>
          {t("scope.list.refresh")}
        </button>
      </header>
      <DataUsageLine kind="captures" version={usageVersion(captures)} />
      <ErrorText error={error} onRetry={onReload} />
      {captures?.length === 0 && <p className="muted">{t("scope.list.empty")}</p>}
      {captures && captures.length > 0 && (
        <div className="table-scroll scope-list-scroll">
          <table className="data-table scope-list-table" aria-label={t("scope.list.heading")}>
            <thead>
              <tr>
                <th className="num">#</th>
                <th>{t("scope.list.name")}</th>
                <th>{t("scope.list.state")}</th>
                <th>{t("scope.list.nodes")}</th>
                <th className="num">{t("scope.list.signals")}</th>
                <th>{t("scope.list.trigger")}</th>
                <th>{t("scope.list.time")}</th>
                <th className="num">{t("scope.list.samples")}</th>
                <th className="num">{t("scope.list.size")}</th>
                <th>{t("scope.list.actions")}</th>
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
                        {t(STATE_WORD[capture.state])}
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
                    <td className="num">{capture.samples.toLocaleString(currentLocale())}</td>
                    <td className="num">{active ? "—" : formatBytes(capture.size_bytes)}</td>
                    <td className="scope-wrap scope-actions-cell">
                      <span className="scope-actions">
                        <button
                          type="button"
                          className="small"
                          disabled={active}
                          title={active ? t("scope.list.openWhileLive") : undefined}
                          aria-label={t("scope.list.openLabel", { id: capture.id })}
                          onClick={() => onOpen(capture)}
                        >
                          {t("scope.list.open")}
                        </button>
                        {EXPORTS.map(({ format, layout, label, labelKey, title }) =>
                          active ? (
                            <span key={label} className="muted small">
                              {labelKey ? t(labelKey) : label}
                            </span>
                          ) : (
                            <a
                              key={label}
                              className="button-link small"
                              href={exportUrl(capture.id, format, layout)}
                              download
                              title={t("scope.list.exportTitle", { what: t(title) })}
                              aria-label={t("scope.list.exportLabel", {
                                id: capture.id,
                                format: labelKey ? t(labelKey) : label,
                              })}
                            >
                              {labelKey ? t(labelKey) : label}
                            </a>
                          ),
                        )}
                        <button
                          type="button"
                          className="small danger"
                          {...operate.gate(t("scope.list.gateDelete"), {
                            disabled: active,
                            title: active ? t("scope.list.stopFirst") : undefined,
                          })}
                          aria-label={t("scope.list.deleteLabel", { id: capture.id })}
                          onClick={() => {
                            remove.clearError();
                            setAsking(capture);
                          }}
                        >
                          {t("scope.list.delete")}
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
          title={t("scope.list.confirmTitle", { id: asking.id })}
          onClose={() => setAsking(null)}
          actions={
            <>
              <button type="button" onClick={() => setAsking(null)}>
                {t("scope.list.cancel")}
              </button>
              <button
                type="button"
                className="danger"
                disabled={remove.busy}
                onClick={() => void remove.run(asking)}
              >
                {t("scope.list.confirm", { id: asking.id })}
              </button>
            </>
          }
        >
          <p>
            {asking.name
              ? t("scope.list.confirmTextNamed", {
                  id: asking.id,
                  name: asking.name,
                  time: formatDateTime(asking.created),
                })
              : t("scope.list.confirmText", {
                  id: asking.id,
                  time: formatDateTime(asking.created),
                })}
          </p>
          <ErrorText error={remove.error} />
        </Dialog>
      )}
    </section>
  );
}
