import { useId, useState, type SubmitEvent, type ReactNode } from "react";

import { api, call, uploadBody } from "../../api/client";
import type { ApiError } from "../../api/errors";
import type { CompareResult, DcfLoadResult } from "../../api/types";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { FilePicker } from "../../components/FilePicker";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { formatValue, odAddress } from "../../lib/format";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";
import { CompareTable } from "./CompareTable";
import { LoadDcfDialog } from "./LoadDcfDialog";

const DCF_TYPES = ".dcf,.eds,.DCF";

/** "node3-cia402.dcf" from `attachment; filename="node3-cia402.dcf"`. */
export function filenameFrom(disposition: string | null, fallback: string): string {
  const match = disposition ? /filename="?([^";]+)"?/i.exec(disposition) : null;
  return match?.[1] ?? fallback;
}

function download(text: string, filename: string): void {
  const url = URL.createObjectURL(new Blob([text], { type: "text/plain" }));
  const link = document.createElement("a");
  link.href = url;
  link.download = filename;
  document.body.append(link);
  link.click();
  link.remove();
  // Revoke later: some browsers read the blob after click() returns.
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}

function LoadResult({ result }: { result: DcfLoadResult }): ReactNode {
  const { t } = useTranslation();
  return (
    <div className="load-result" role="status">
      <p>
        {t("params.set.result", {
          written: result.written,
          skipped: result.skipped,
          failed: result.failed.length,
          differing: result.differences.length,
        })}
      </p>
      {result.warnings.length > 0 && (
        <ul className="compact-list" aria-label={t("params.set.warnings")}>
          {result.warnings.map((warning) => (
            <li key={warning} className="warn-text">
              {warning}
            </li>
          ))}
        </ul>
      )}
      {result.failed.length > 0 && (
        <ul className="compact-list">
          {result.failed.map((f) => (
            <li key={`${f.index}:${f.subindex}`}>
              <span className="mono">{odAddress(f.index, f.subindex)}</span>{" "}
              {t("params.set.failed", { name: f.name })}{" "}
              <span className="error-text inline-error">
                {f.abort_code ? `${f.abort_code} — ` : ""}
                {f.message}
              </span>
            </li>
          ))}
        </ul>
      )}
      {result.differences.length > 0 && (
        <ul className="compact-list">
          {result.differences.map((d) => (
            <li key={`${d.index}:${d.subindex}`}>
              <span className="mono">{odAddress(d.index, d.subindex)}</span>{" "}
              {t("params.set.expected", { name: d.name })}{" "}
              <span className="mono">{formatValue(d.expected)}</span>
              {t("params.set.deviceHas")} <span className="mono">{formatValue(d.actual)}</span>
            </li>
          ))}
        </ul>
      )}
    </div>
  );
}

function CompareDialog({
  onCompare,
  onClose,
  busy,
  error,
}: {
  onCompare: (file: File | null) => void;
  onClose: () => void;
  busy: boolean;
  error: ApiError | null;
}): ReactNode {
  const { t } = useTranslation();
  const fileId = useId();
  const [file, setFile] = useState<File | null>(null);
  function submit(event: SubmitEvent): void {
    event.preventDefault();
    onCompare(file);
  }
  return (
    <Dialog
      title={t("params.compareDialog.title")}
      onClose={onClose}
      actions={
        <>
          <button type="button" onClick={onClose}>
            {t("params.cancel")}
          </button>
          <button type="submit" form={`${fileId}-form`} className="primary" disabled={busy}>
            {t("params.compareDialog.submit")}
          </button>
        </>
      }
    >
      <form id={`${fileId}-form`} onSubmit={submit}>
        <label htmlFor={fileId}>{t("params.compareDialog.file")}</label>
        <input
          id={fileId}
          type="file"
          accept={DCF_TYPES}
          onChange={(e) => setFile(e.target.files?.[0] ?? null)}
        />
      </form>
      <p className="muted small">{t("params.compareDialog.hint")}</p>
      {busy && <Spinner label={t("params.compareDialog.comparing")} />}
      <ErrorText error={error} />
    </Dialog>
  );
}

/** Save the node's configuration as DCF, load one onto it, or compare. */
export function ParamSetPanel({ node }: { node: number }): ReactNode {
  const [loadResult, setLoadResult] = useState<DcfLoadResult | null>(null);
  const [comparison, setComparison] = useState<{ result: CompareResult; withFile: boolean } | null>(
    null,
  );
  const [compareOpen, setCompareOpen] = useState(false);
  // a picked DCF and what it would change: nothing is written before the user confirms
  const [pending, setPending] = useState<{ file: File; preview: CompareResult } | null>(null);

  const save = useAction(async () => {
    const { data, error, response } = await api.GET("/api/nodes/{node}/dcf", {
      params: { path: { node } },
      parseAs: "text",
    });
    // parseAs "text" also returns the error body as text: re-parse it for the error helper.
    const text = await call(Promise.resolve({ data, error: parseMaybeJson(error), response }));
    download(text, filenameFrom(response.headers.get("Content-Disposition"), `node${node}.dcf`));
  });
  const preview = useAction(async (file: File) => {
    setLoadResult(null);
    const result = await call(
      api.POST("/api/nodes/{node}/compare", { params: { path: { node } }, ...uploadBody(file) }),
    );
    setPending({ file, preview: result });
  });
  const load = useAction(async (file: File, confirmIdentity: boolean) => {
    const upload = uploadBody(file, confirmIdentity ? { confirm: "true" } : {});
    const result = await call(
      api.POST("/api/nodes/{node}/dcf", {
        params: { path: { node } },
        body: { ...upload.body, confirm: confirmIdentity },
        bodySerializer: upload.bodySerializer,
      }),
    );
    setPending(null);
    setLoadResult(result);
    // the comparison shows the node as it is after the load, not as it was before
    const after = await call(
      api.POST("/api/nodes/{node}/compare", { params: { path: { node } }, ...uploadBody(file) }),
    );
    setComparison({ result: after, withFile: true });
  });
  const compare = useAction(async (file: File | null) => {
    const result = await call(
      api.POST("/api/nodes/{node}/compare", { params: { path: { node } }, ...uploadBody(file) }),
    );
    setComparison({ result, withFile: file !== null });
    setCompareOpen(false);
  });
  const { t } = useTranslation();
  const busy = save.busy || preview.busy || load.busy || compare.busy;
  const configure = useMay("configure");

  return (
    <section className="card" aria-labelledby="paramset-heading">
      <header className="card-header">
        <h2 id="paramset-heading">{t("params.set.heading")}</h2>
        <button type="button" disabled={busy} onClick={() => void save.run()}>
          {t("params.set.saveDcf")}
        </button>
        <FilePicker
          label={t("params.set.loadDcf")}
          accept={DCF_TYPES}
          {...configure.gate(t("params.set.gateLoad"), { disabled: busy })}
          onFile={(f) => void preview.run(f)}
        />
        <button type="button" disabled={busy} onClick={() => setCompareOpen(true)}>
          {t("params.set.compare")}
        </button>
        {busy && <Spinner label={t("params.set.working")} />}
      </header>
      <ErrorText
        error={
          save.error ??
          preview.error ??
          (pending ? null : load.error) ??
          (compareOpen ? null : compare.error)
        }
      />
      {pending && (
        <LoadDcfDialog
          node={node}
          filename={pending.file.name}
          preview={pending.preview}
          busy={load.busy}
          error={load.error}
          onWrite={(confirmIdentity) => void load.run(pending.file, confirmIdentity)}
          onClose={() => {
            setPending(null);
            load.clearError();
          }}
        />
      )}
      {loadResult && <LoadResult result={loadResult} />}
      {comparison && <CompareTable result={comparison.result} withFile={comparison.withFile} />}
      {compareOpen && (
        <CompareDialog
          busy={compare.busy}
          error={compare.error}
          onClose={() => setCompareOpen(false)}
          onCompare={(f) => void compare.run(f)}
        />
      )}
    </section>
  );
}

function parseMaybeJson(body: unknown): unknown {
  if (typeof body !== "string") return body;
  try {
    return JSON.parse(body) as unknown;
  } catch {
    return body;
  }
}
