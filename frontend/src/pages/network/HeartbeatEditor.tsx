import { useState, type SubmitEvent, type ReactNode } from "react";

import { api, call } from "../../api/client";
import { ErrorText } from "../../components/ErrorText";
import { useTranslation } from "../../i18n";
import { useAction, useApi } from "../../lib/useApi";
import { useMay } from "../../session/context";

/** The node's heartbeat producer time (1017h): read on show, written on Set. Below 10 ms the
 * server asks first (the node alone would put 100+ frames/s on the bus); "Set anyway" confirms. */
export function HeartbeatEditor({ node }: { node: number }): ReactNode {
  const { t } = useTranslation();
  const current = useApi(
    (signal) =>
      call(api.GET("/api/nodes/{node}/heartbeat", { params: { path: { node } }, signal })),
    `hb-${node}`,
  );
  const [text, setText] = useState<string | null>(null);
  const [inputError, setInputError] = useState<string | null>(null);
  const configure = useMay("configure");
  const save = useAction(async (producer_ms: number, confirm: boolean) => {
    const result = await call(
      api.PUT("/api/nodes/{node}/heartbeat", {
        params: { path: { node } },
        body: { producer_ms, confirm },
      }),
    );
    current.setData(() => result);
    setText(null);
  });
  const shown = text ?? (current.data ? String(current.data.producer_ms) : "");

  function submit(event: SubmitEvent): void {
    event.preventDefault();
    const value = Number(shown);
    if (!/^\d+$/.test(shown.trim()) || value > 65535) {
      setInputError(t("network.heartbeat.range"));
      return;
    }
    setInputError(null);
    void save.run(value, false);
  }

  const failure = save.error ?? current.error ?? null;
  const error = inputError ?? failure?.describe() ?? null;
  const needsConfirm = inputError === null && save.error?.kind === "confirmation_required";
  return (
    <form className="hb-editor" onSubmit={submit}>
      <input
        className="narrow num"
        inputMode="numeric"
        aria-label={t("network.heartbeat.label", { node })}
        value={shown}
        placeholder={current.loading ? "…" : "—"}
        aria-invalid={error !== null}
        title={error ?? t("network.heartbeat.title")}
        onChange={(e) => setText(e.target.value)}
      />
      <span className="unit">ms</span>
      <button
        type="submit"
        className="small"
        {...configure.gate(t("network.gate.heartbeat"), {
          disabled: save.busy || text === null,
        })}
      >
        {t("network.heartbeat.set")}
      </button>
      {inputError ? (
        <ErrorText error={inputError} inline />
      ) : (
        <ErrorText error={failure} inline onRetry={current.reload} />
      )}
      {needsConfirm && (
        <button
          type="button"
          className="small danger"
          disabled={save.busy || !configure.allowed}
          onClick={() => void save.run(Number(shown), true)}
        >
          {t("network.heartbeat.setAnyway")}
        </button>
      )}
    </form>
  );
}
