import { useId, useState, type SubmitEvent, type ReactNode } from "react";
import { useNavigate } from "react-router";

import { api, call } from "../../api/client";
import type { components } from "../../api/schema";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { useAction } from "../../lib/useApi";
import { useLiveStore } from "../../live/context";
import { refreshNodes } from "../../live/nodes";
import { nodeUrl } from "../../nav/paths";
import { useMay } from "../../session/context";

type NodeIdOptions = components["schemas"]["NodeIdOptions"];

/** What the node's new page says: "Node 3 is now node 5" in its language, the server's steps. */
export interface StepsNotice {
  oldNode: number;
  newNode: number;
  steps: readonly string[];
}

/** Change the node id: the server writes it, stores, resets and follows the node. */
export function NodeIdWizard({ node }: { node: number }): ReactNode {
  const { t } = useTranslation();
  const inputId = useId();
  const navigate = useNavigate();
  const store = useLiveStore();
  const [open, setOpen] = useState(false);
  const [text, setText] = useState("");
  const [inputError, setInputError] = useState<string | null>(null);
  // whether the drive's id can be set over CANopen at all: asked when the dialog opens
  const [options, setOptions] = useState<NodeIdOptions | null>(null);
  const fetchOptions = useAction(async () => {
    setOptions(
      await call(api.GET("/api/nodes/{node}/node-id-options", { params: { path: { node } } })),
    );
  });
  const change = useAction(async (newNode: number) => {
    let result;
    try {
      result = await call(
        api.POST("/api/nodes/{node}/change-node-id", {
          params: { path: { node } },
          body: { new_node: newNode, confirm: true },
        }),
      );
    } catch (error) {
      // A change that failed half-way (written and stored, no boot-up seen) can still have
      // moved the node: show the list as the server now sees it.
      void refreshNodes(store);
      throw error;
    }
    store.upsertInfo(result.node);
    void refreshNodes(store); // the old id is gone from the list
    const notice: StepsNotice = {
      oldNode: result.old_node,
      newNode: result.new_node,
      steps: result.steps,
    };
    setOpen(false);
    void navigate(nodeUrl(result.new_node), { state: { notice } });
  });

  const configure = useMay("configure");
  const title = t("params.nodeId.title", { node });
  const close = (): void => setOpen(false);

  function submit(event: SubmitEvent): void {
    event.preventDefault();
    const value = Number(text.trim());
    if (!/^\d+$/.test(text.trim()) || value < 1 || value > 127) {
      setInputError(t("params.nodeId.invalid"));
      return;
    }
    if (value === node) {
      setInputError(t("params.nodeId.same", { node }));
      return;
    }
    setInputError(null);
    void change.run(value);
  }

  return (
    <>
      <button
        type="button"
        onClick={() => {
          setOpen(true);
          void fetchOptions.run();
        }}
        {...configure.gate(t("params.nodeId.gate"))}
      >
        {t("params.nodeId.open")}
      </button>
      {open && !options && (
        <Dialog
          title={title}
          onClose={close}
          actions={
            <button type="button" onClick={close}>
              {t("params.cancel")}
            </button>
          }
        >
          {fetchOptions.busy && <Spinner label={t("params.nodeId.asking")} />}
          <ErrorText error={fetchOptions.error} onRetry={() => void fetchOptions.run()} />
        </Dialog>
      )}
      {open && options && !options.settable && (
        <Dialog
          title={title}
          onClose={close}
          actions={
            <button type="button" onClick={close}>
              {t("params.close")}
            </button>
          }
        >
          <p role="status">{options.note}</p>
          <p>{t("params.nodeId.elsewhere")}</p>
        </Dialog>
      )}
      {open && options?.settable && (
        <Dialog
          title={title}
          onClose={close}
          actions={
            <>
              <button type="button" onClick={close}>
                {t("params.cancel")}
              </button>
              <button
                type="submit"
                form={`${inputId}-form`}
                className="primary"
                disabled={change.busy}
              >
                {t("params.nodeId.submit")}
              </button>
              {change.busy && <Spinner label={t("params.nodeId.changing")} />}
            </>
          }
        >
          <form id={`${inputId}-form`} onSubmit={submit} noValidate>
            <label htmlFor={inputId}>{t("params.nodeId.label")}</label>
            <input
              id={inputId}
              className="narrow num"
              inputMode="numeric"
              value={text}
              aria-invalid={inputError !== null}
              onChange={(e) => setText(e.target.value)}
            />
          </form>
          <p className="muted small">{options.note}</p>
          <p>{t("params.nodeId.serverWill")}</p>
          <ol className="steps">
            <li>{t("params.nodeId.stepWrite")}</li>
            <li>{t("params.nodeId.stepStore")}</li>
            <li>{t("params.nodeId.stepReset")}</li>
            <li>{t("params.nodeId.stepFollow")}</li>
          </ol>
          <p className="muted small">{t("params.nodeId.others", { node })}</p>
          <ErrorText error={inputError ?? change.error} />
        </Dialog>
      )}
    </>
  );
}
