import type { ReactNode } from "react";

import { api, call } from "../../api/client";
import { useMay } from "../../session/context";
import { ConfirmAction } from "./ConfirmAction";

const BOOT_WAIT_MS = 8000;
const POLL_MS = 250;

function sleep(ms: number): Promise<void> {
  return new Promise((resolve) => setTimeout(resolve, ms));
}

/** Restored defaults take effect only after a reset: offer it right where the restore was
 * done, wait until the node answers again, then let the page show the values it now has. */
export function ResetAfterRestore({
  node,
  onBack,
}: {
  node: number;
  onBack: () => void;
}): ReactNode {
  const configure = useMay("configure");
  async function reset(): Promise<string> {
    await call(
      api.POST("/api/nodes/{node}/nmt", {
        params: { path: { node } },
        body: { command: "reset-node" },
      }),
    );
    const deadline = Date.now() + BOOT_WAIT_MS;
    while (Date.now() < deadline) {
      await sleep(POLL_MS);
      try {
        // the node answers SDO again once it has booted (Pre-operational)
        await call(
          api.GET("/api/nodes/{node}/sdo/{index}/{subindex}", {
            params: { path: { node, index: "1000", subindex: "0" } },
          }),
        );
        onBack();
        return `Node ${node} was reset and answers again: the values below are the ones it runs with now.`;
      } catch {
        // still booting
      }
    }
    throw new Error(
      `node ${node} did not answer within ${BOOT_WAIT_MS / 1000} s after the reset; check its power and wiring, then use Read again`,
    );
  }

  return (
    <section className="card notice" role="status" aria-label="Restored defaults">
      <p>
        Node {node} restored its default parameters. They take effect after a reset of the node.
      </p>
      <ConfirmAction
        label={`Reset node ${node} now`}
        confirmLabel="Reset node"
        {...configure.gate("reset the node")}
        explanation={
          <p>
            Sends NMT "reset node" to node {node}: the drive restarts with the restored defaults.
            Its communication stops for a moment and a running axis is disabled; parameters that
            were not stored are lost.
          </p>
        }
        onConfirm={reset}
      />
    </section>
  );
}
