import { useState, type ReactNode } from "react";

import { api, call } from "../api/client";
import { asApiError, type ApiError } from "../api/errors";
import { useTranslation } from "../i18n";
import { useMay } from "../session/context";

/** An error shown where it happened; SDO aborts read "0x06010002 — Attempt to write …".
 *
 * A node in NMT Stopped has no SDO: the error offers the way out right there (set the node
 * Pre-operational), then `onRetry` lets the page load again. */
export function ErrorText({
  error,
  onRetry,
  inline = false,
}: {
  error: ApiError | string | null | undefined;
  onRetry?: () => void;
  inline?: boolean;
}): ReactNode {
  if (!error) return null;
  const text = typeof error === "string" ? error : error.describe();
  const stoppedNode =
    typeof error !== "string" && error.kind === "node_stopped" ? error.node : null;
  const Tag = inline ? "span" : "p";
  return (
    <Tag className={inline ? "error-text small" : "error-text"} role="alert">
      {text}
      {stoppedNode !== null && <StartButton node={stoppedNode} onDone={onRetry} />}
    </Tag>
  );
}

function StartButton({ node, onDone }: { node: number; onDone?: () => void }): ReactNode {
  const { t } = useTranslation();
  const configure = useMay("configure");
  const [busy, setBusy] = useState(false);
  const [failed, setFailed] = useState<string | null>(null);

  async function preOperational(): Promise<void> {
    setBusy(true);
    setFailed(null);
    try {
      await call(
        api.POST("/api/nodes/{node}/nmt", {
          params: { path: { node } },
          body: { command: "pre-operational" },
        }),
      );
      onDone?.();
    } catch (error) {
      setFailed(asApiError(error).describe());
    } finally {
      setBusy(false);
    }
  }

  return (
    <>
      {" "}
      <button
        type="button"
        className="small"
        onClick={() => void preOperational()}
        {...configure.gate(t("nmt.gateChangeState"), { disabled: busy })}
      >
        {t("nmt.setPreOperational", { node })}
      </button>
      {failed && <span className="error-text small"> {failed}</span>}
    </>
  );
}
