import type { ReactNode } from "react";

import { api, call } from "../../api/client";
import { useTranslation } from "../../i18n";
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
  const { t } = useTranslation();
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
        return t("params.reset.answers", { node });
      } catch {
        // still booting
      }
    }
    throw new Error(t("params.reset.noAnswer", { node, seconds: BOOT_WAIT_MS / 1000 }));
  }

  return (
    <section className="card notice" role="status" aria-label={t("params.reset.region")}>
      <p>{t("params.reset.restored", { node })}</p>
      <ConfirmAction
        label={t("params.reset.label", { node })}
        confirmLabel={t("params.reset.confirm")}
        {...configure.gate(t("params.reset.gate"))}
        explanation={<p>{t("params.reset.explanation", { node })}</p>}
        onConfirm={reset}
      />
    </section>
  );
}
