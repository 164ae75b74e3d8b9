import { useState, type ReactNode } from "react";

import { api, call, uploadBody } from "../../api/client";
import type { OdCheckResult } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { FilePicker, OD_FILE_TYPES } from "../../components/FilePicker";
import { LintTable } from "../../components/LintTable";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { hex } from "../../lib/format";
import { useAction } from "../../lib/useApi";

function Summary({ result }: { result: OdCheckResult }): ReactNode {
  const { t } = useTranslation();
  const counts = { error: 0, warning: 0, info: 0 };
  for (const w of result.warnings) counts[w.severity] += 1;
  return (
    <>
      <dl className="facts" aria-label={t("logs.tools.check.summary")}>
        <dt>{t("logs.tools.check.file")}</dt>
        <dd className="mono">{result.filename}</dd>
        <dt>{t("logs.tools.check.format")}</dt>
        <dd>{result.format.toUpperCase()}</dd>
        <dt>{t("logs.tools.check.objects")}</dt>
        <dd className="num">{result.objects}</dd>
        <dt>{t("logs.tools.check.vendor")}</dt>
        <dd>
          {result.device.vendor_name || "—"}{" "}
          <span className="mono">{hex(result.device.vendor_number)}</span>
        </dd>
        <dt>{t("logs.tools.check.product")}</dt>
        <dd>
          {result.device.product_name || "—"}{" "}
          <span className="mono">{hex(result.device.product_number)}</span>
        </dd>
        <dt>{t("logs.tools.check.findings")}</dt>
        <dd>
          {t("logs.tools.check.counts", {
            errors: counts.error,
            warnings: counts.warning,
            notes: counts.info,
          })}
        </dd>
      </dl>
      <LintTable
        warnings={result.warnings}
        caption={t("logs.tools.check.caption", { name: result.filename })}
      />
    </>
  );
}

/** Lint any EDS/DCF/XDD file without applying it to a node (POST /api/od/check). */
export function EdsCheckPanel(): ReactNode {
  const { t } = useTranslation();
  const [result, setResult] = useState<OdCheckResult | null>(null);
  const check = useAction(async (file: File) => {
    setResult(null);
    setResult(await call(api.POST("/api/od/check", uploadBody(file))));
  });
  return (
    <section className="card" aria-labelledby="check-heading">
      <header className="card-header">
        <h2 id="check-heading">{t("logs.tools.check.heading")}</h2>
        <FilePicker
          label={t("logs.tools.check.choose")}
          accept={OD_FILE_TYPES}
          disabled={check.busy}
          onFile={(f) => void check.run(f)}
        />
        {check.busy && <Spinner label={t("logs.tools.check.checking")} />}
      </header>
      <p className="muted small">{t("logs.tools.check.intro")}</p>
      <ErrorText error={check.error} />
      {result && <Summary result={result} />}
    </section>
  );
}
