import { useState, type ReactNode } from "react";

import { api, call, uploadBody } from "../../api/client";
import type { OdCheckResult } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { FilePicker, OD_FILE_TYPES } from "../../components/FilePicker";
import { LintTable } from "../../components/LintTable";
import { Spinner } from "../../components/Spinner";
import { hex } from "../../lib/format";
import { useAction } from "../../lib/useApi";

function Summary({ result }: { result: OdCheckResult }): ReactNode {
  const counts = { error: 0, warning: 0, info: 0 };
  for (const w of result.warnings) counts[w.severity] += 1;
  return (
    <>
      <dl className="facts" aria-label="File summary">
        <dt>File</dt>
        <dd className="mono">{result.filename}</dd>
        <dt>Format</dt>
        <dd>{result.format.toUpperCase()}</dd>
        <dt>Objects</dt>
        <dd className="num">{result.objects}</dd>
        <dt>Vendor</dt>
        <dd>
          {result.device.vendor_name || "—"}{" "}
          <span className="mono">{hex(result.device.vendor_number)}</span>
        </dd>
        <dt>Product</dt>
        <dd>
          {result.device.product_name || "—"}{" "}
          <span className="mono">{hex(result.device.product_number)}</span>
        </dd>
        <dt>Findings</dt>
        <dd>
          {counts.error} errors, {counts.warning} warnings, {counts.info} notes
        </dd>
      </dl>
      <LintTable warnings={result.warnings} caption={`Findings in ${result.filename}`} />
    </>
  );
}

/** Lint any EDS/DCF/XDD file without applying it to a node (POST /api/od/check). */
export function EdsCheckPanel(): ReactNode {
  const [result, setResult] = useState<OdCheckResult | null>(null);
  const check = useAction(async (file: File) => {
    setResult(null);
    setResult(await call(api.POST("/api/od/check", uploadBody(file))));
  });
  return (
    <section className="card" aria-labelledby="check-heading">
      <header className="card-header">
        <h2 id="check-heading">Check an EDS file</h2>
        <FilePicker
          label="Choose EDS file to check…"
          accept={OD_FILE_TYPES}
          disabled={check.busy}
          onFile={(f) => void check.run(f)}
        />
        {check.busy && <Spinner label="Checking" />}
      </header>
      <p className="muted small">
        Reads an EDS, DCF or XDD file and lists what is wrong or unusual in it, without changing any
        node.
      </p>
      <ErrorText error={check.error} />
      {result && <Summary result={result} />}
    </section>
  );
}
