import { useCallback, useState, type ReactNode } from "react";
import { useLocation } from "react-router";

import { api, call } from "../../api/client";
import type { ParamWriteResult } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
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
  return typeof notice === "object" && notice !== null && "steps" in notice;
}

/** Steps the server carried out for a node-id change, shown on the node's new page. */
function Notice(): ReactNode {
  // Router state is whatever the previous page put there: checked before use.
  const state: unknown = useLocation().state;
  if (!isNotice(state)) return null;
  return (
    <section className="card notice" role="status">
      <h2>{state.notice.title}</h2>
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
            <h2 id="params-heading">Parameters</h2>
            <button type="button" disabled={params.loading} onClick={params.reload}>
              Read again
            </button>
            {params.loading && <Spinner label="Reading parameters" />}
            <span className="spacer" />
            <ConfirmAction
              label="Store parameters"
              confirmLabel="Store"
              {...configure.gate("store parameters")}
              explanation={
                <p>
                  Writes "save" to 1010h:01: node {node} copies its current parameters into
                  non-volatile memory and keeps them after a reset or power cycle. Parameters marked
                  "after store + reset" only take effect once they are stored.
                </p>
              }
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
              label="Restore defaults"
              confirmLabel="Restore defaults"
              {...configure.gate("restore the defaults")}
              explanation={
                <p>
                  Writes "load" to 1011h:01: node {node} replaces its stored parameters with the
                  factory defaults. They take effect after the next reset; values you have not saved
                  elsewhere (Save DCF) are lost.
                </p>
              }
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
                    <th scope="col">Name</th>
                    <th scope="col">Label</th>
                    <th scope="col">Value</th>
                    <th scope="col">Unit</th>
                    <th scope="col">Range</th>
                    <th scope="col">Default</th>
                    <th scope="col">Takes effect</th>
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
          <h2>No parameter catalogue</h2>
          <p>
            Node {node} uses a generic profile, so ServoDesk has no list of named parameters for it.
            Every object is still readable and writable on the Object dictionary tab, and its
            configuration can be saved, loaded and compared as a DCF below.
          </p>
        </section>
      )}
      <ParamSetPanel node={node} />
    </div>
  );
}
