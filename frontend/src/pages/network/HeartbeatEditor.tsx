import { useState, type SubmitEvent, type ReactNode } from "react";

import { api, call } from "../../api/client";
import { useAction, useApi } from "../../lib/useApi";

/** The node's heartbeat producer time (1017h): read on show, written on Set. */
export function HeartbeatEditor({ node }: { node: number }): ReactNode {
  const current = useApi(
    (signal) =>
      call(api.GET("/api/nodes/{node}/heartbeat", { params: { path: { node } }, signal })),
    `hb-${node}`,
  );
  const [text, setText] = useState<string | null>(null);
  const [inputError, setInputError] = useState<string | null>(null);
  const save = useAction(async (producer_ms: number) => {
    const result = await call(
      api.PUT("/api/nodes/{node}/heartbeat", { params: { path: { node } }, body: { producer_ms } }),
    );
    current.setData(() => result);
    setText(null);
  });
  const shown = text ?? (current.data ? String(current.data.producer_ms) : "");

  function submit(event: SubmitEvent): void {
    event.preventDefault();
    const value = Number(shown);
    if (!/^\d+$/.test(shown.trim()) || value > 65535) {
      setInputError("0–65535 ms (0 turns the heartbeat off)");
      return;
    }
    setInputError(null);
    void save.run(value);
  }

  const error = inputError ?? save.error?.describe() ?? current.error?.describe() ?? null;
  return (
    <form className="hb-editor" onSubmit={submit}>
      <input
        className="narrow num"
        inputMode="numeric"
        aria-label={`Heartbeat producer time of node ${node} (ms)`}
        value={shown}
        placeholder={current.loading ? "…" : "—"}
        aria-invalid={error !== null}
        title={error ?? "Heartbeat producer time (1017h), ms"}
        onChange={(e) => setText(e.target.value)}
      />
      <span className="unit">ms</span>
      <button type="submit" className="small" disabled={save.busy || text === null}>
        Set
      </button>
      {error && (
        <span className="error-text small" role="alert">
          {error}
        </span>
      )}
    </form>
  );
}
