import type { ReactNode } from "react";

import { formatAbortCode } from "../../api/errors";
import { useTranslation } from "../../i18n";
import type { ApplyOutcome } from "./pdoApi";

/** What came of the last apply: the read-back, or the step that failed and what was restored. */
export function ApplyResult({
  outcome,
  onClose,
}: {
  outcome: ApplyOutcome;
  onClose: () => void;
}): ReactNode {
  const { t } = useTranslation();
  const close = (
    <button type="button" className="small" onClick={onClose}>
      {t("pdo.result.dismiss")}
    </button>
  );
  if (outcome.result === "applied") {
    const valid = outcome.pdos.filter((p) => p.valid).length;
    return (
      <section className="card notice" role="status" aria-label={t("pdo.result.label")}>
        <header className="card-header">
          <h2>{t("pdo.result.applied")}</h2>
          <span className="spacer" />
          {close}
        </header>
        <p>{t("pdo.result.readBack", { total: outcome.pdos.length, valid })}</p>
      </section>
    );
  }
  if (outcome.result === "rejected") {
    return (
      <section className="card pdo-failure" role="alert" aria-label={t("pdo.result.label")}>
        <header className="card-header">
          <h2>{t("pdo.result.notApplied")}</h2>
          <span className="spacer" />
          {close}
        </header>
        <p>{outcome.message}</p>
        <p className="small">{t("pdo.result.eachProblem")}</p>
      </section>
    );
  }
  const { failure } = outcome;
  return (
    <section className="card pdo-failure" role="alert" aria-label={t("pdo.result.label")}>
      <header className="card-header">
        <h2>{t("pdo.result.failed")}</h2>
        <span className="spacer" />
        {close}
      </header>
      <dl className="facts">
        <dt>{t("pdo.result.step")}</dt>
        <dd>{failure.step}</dd>
        <dt>{t("pdo.result.answer")}</dt>
        <dd className="error-text">
          {failure.abort_code && (
            <span className="mono">{formatAbortCode(failure.abort_code)} — </span>
          )}
          {failure.message}
        </dd>
        <dt>{t("pdo.result.device")}</dt>
        <dd>{failure.restored ? t("pdo.result.restored") : t("pdo.result.notRestored")}</dd>
      </dl>
    </section>
  );
}
