import { useCallback, useState, type ReactNode } from "react";
import { useLocation } from "react-router";

import { api, call } from "../../api/client";
import type { ParamWriteResult } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { useApi } from "../../lib/useApi";
import { useMay } from "../../session/context";
import { BitrateWizard } from "./BitrateWizard";
import { ConfirmAction } from "./ConfirmAction";
import { NodeIdWizard, type StepsNotice } from "./NodeIdWizard";
import { ParamRow } from "./ParamRow";
import { ParamSetPanel } from "./ParamSetPanel";
import { ResetAfterRestore } from "./ResetAfterRestore";

function isNotice(value: unknown): value is { notice: StepsNotice } {
  if (typeof value !== "object" || value === null || !("notice" in value)) return false;
  const { notice } = value;
  return (
    typeof notice === "object" &&
    notice !== null &&
    "steps" in notice &&
    "oldNode" in notice &&
    "newNode" in notice
  );
}

/** Steps the server carried out for a node-id change, shown on the node's new page. */
function Notice(): ReactNode {
  const { t } = useTranslation();
  // Router state is whatever the previous page put there: checked before use.
  const state: unknown = useLocation().state;
  if (!isNotice(state)) return null;
  return (
    <section className="card notice" role="status">
      <h2>{t("params.nodeId.moved", { old: state.notice.oldNode, new: state.notice.newNode })}</h2>
      <ol className="steps">
        {state.notice.steps.map((step, i) => (
          <li key={i}>{step}</li>
        ))}
      </ol>
    </section>
  );
}

/** The drive's parameters by their manual names (PA-14 …), and the node's parameter set. */
export function ParamsPage({ node }: { node: number }): ReactNode {
  const { t } = useTranslation();
  const params = useApi(
    (signal) => call(api.GET("/api/nodes/{node}/params", { params: { path: { node } }, signal })),
    `params-${node}`,
  );
  const { setData } = params;
  const onWritten = useCallback(
    (result: ParamWriteResult) =>
      setData((old) => old?.map((p) => (p.name === result.param.name ? result.param : p))),
    [setData],
  );
  const [restored, setRestored] = useState(false);
  const configure = useMay("configure");
  const list = params.data;
  const generic = list !== undefined && list.length === 0;

  return (
    <div className="params-page">
      <Notice />
      {restored && <ResetAfterRestore node={node} onBack={params.reload} />}
      {!generic && (
        <section className="card" aria-labelledby="params-heading">
          <header className="card-header">
            <h2 id="params-heading">{t("params.page.heading")}</h2>
            <button type="button" disabled={params.loading} onClick={params.reload}>
              {t("params.page.readAgain")}
            </button>
            {params.loading && <Spinner label={t("params.page.reading")} />}
            <span className="spacer" />
            <ConfirmAction
              label={t("params.page.store.label")}
              confirmLabel={t("params.page.store.confirm")}
              {...configure.gate(t("params.page.store.gate"))}
              explanation={<p>{t("params.page.store.explanation", { node })}</p>}
              onConfirm={async () =>
                (
                  await call(
                    api.POST("/api/nodes/{node}/store", {
                      params: { path: { node } },
                      body: { confirm: true },
                    }),
                  )
                ).message
              }
            />
            <ConfirmAction
              label={t("params.page.restore.label")}
              confirmLabel={t("params.page.restore.confirm")}
              {...configure.gate(t("params.page.restore.gate"))}
              explanation={<p>{t("params.page.restore.explanation", { node })}</p>}
              onConfirm={async () => {
                await call(
                  api.POST("/api/nodes/{node}/restore-defaults", {
                    params: { path: { node } },
                    body: { confirm: true },
                  }),
                );
                params.reload();
                setRestored(true);
                // the notice above the table says it, with the reset button: not twice
                return null;
              }}
            />
            <NodeIdWizard node={node} />
            <BitrateWizard node={node} />
          </header>
          <ErrorText error={params.error} onRetry={params.reload} />
          {list && (
            <div className="table-scroll">
              <table className="data-table params-table">
                <thead>
                  <tr>
                    <th scope="col">{t("params.page.column.name")}</th>
                    <th scope="col">{t("params.page.column.label")}</th>
                    <th scope="col">{t("params.page.column.value")}</th>
                    <th scope="col">{t("params.page.column.unit")}</th>
                    <th scope="col">{t("params.page.column.range")}</th>
                    <th scope="col">{t("params.page.column.default")}</th>
                    <th scope="col">{t("params.page.column.takesEffect")}</th>
                  </tr>
                </thead>
                <tbody>
                  {list.map((param) => (
                    <ParamRow key={param.name} node={node} param={param} onWritten={onWritten} />
                  ))}
                </tbody>
              </table>
            </div>
          )}
        </section>
      )}
      {generic && (
        <section className="card">
          <h2>{t("params.page.noCatalogue")}</h2>
          <p>{t("params.page.generic", { node })}</p>
        </section>
      )}
      <ParamSetPanel node={node} />
    </div>
  );
}
