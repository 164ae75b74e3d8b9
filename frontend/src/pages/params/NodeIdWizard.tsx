import { useId, useState, type SubmitEvent, type ReactNode } from "react";
import { useNavigate } from "react-router";

import { api, call } from "../../api/client";
import type { components } from "../../api/schema";
import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useAction } from "../../lib/useApi";
import { useLiveStore } from "../../live/context";
import { refreshNodes } from "../../live/nodes";
import { nodeUrl } from "../../nav/paths";
import { useMay } from "../../session/context";

type NodeIdOptions = components["schemas"]["NodeIdOptions"];

export interface StepsNotice {
  title: string;
  steps: readonly string[];
}

/** Change the node id: the server writes it, stores, resets and follows the node. */
export function NodeIdWizard({ node }: { node: number }): ReactNode {
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
      title: `Node ${result.old_node} is now node ${result.new_node}`,
      steps: result.steps,
    };
    setOpen(false);
    void navigate(nodeUrl(result.new_node), { state: { notice } });
  });

  const configure = useMay("configure");
  const title = `Change the node ID of node ${node}`;
  const close = (): void => setOpen(false);

  function submit(event: SubmitEvent): void {
    event.preventDefault();
    const value = Number(text.trim());
    if (!/^\d+$/.test(text.trim()) || value < 1 || value > 127) {
      setInputError("A node id is 1–127");
      return;
    }
    if (value === node) {
      setInputError(`The node already has id ${node}`);
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
        {...configure.gate("change the node ID")}
      >
        Change node ID…
      </button>
      {open && !options && (
        <Dialog
          title={title}
          onClose={close}
          actions={
            <button type="button" onClick={close}>
              Cancel
            </button>
          }
        >
          {fetchOptions.busy && <Spinner label="Asking how the node's id is set" />}
          <ErrorText error={fetchOptions.error} onRetry={() => void fetchOptions.run()} />
        </Dialog>
      )}
      {open && options && !options.settable && (
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
          <p>After changing it there, scan the bus on the Network page.</p>
        </Dialog>
      )}
      {open && options?.settable && (
        <Dialog
          title={title}
          onClose={close}
          actions={
            <>
              <button type="button" onClick={close}>
                Cancel
              </button>
              <button
                type="submit"
                form={`${inputId}-form`}
                className="primary"
                disabled={change.busy}
              >
                Change node ID
              </button>
              {change.busy && <Spinner label="Changing node ID" />}
            </>
          }
        >
          <form id={`${inputId}-form`} onSubmit={submit} noValidate>
            <label htmlFor={inputId}>New node ID (1–127)</label>
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
          <p>The server will:</p>
          <ol className="steps">
            <li>write the new id to the drive's node-id parameter,</li>
            <li>store the parameters (1010h) so the id survives a power cycle,</li>
            <li>reset the node,</li>
            <li>wait for its boot-up message at the new id and move this node there.</li>
          </ol>
          <p className="muted small">
            Anything else on the bus that talks to node {node} by id (a PLC, PDO COB-IDs derived
            from the id) has to follow.
          </p>
          <ErrorText error={inputError ?? change.error} />
        </Dialog>
      )}
    </>
  );
}
