import { memo, useId, useState, type SubmitEvent, type ReactNode } from "react";

import { api, call } from "../../api/client";
import type { Param, ParamWriteResult } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { formatValue } from "../../lib/format";
import { useAction } from "../../lib/useApi";
import { useMay } from "../../session/context";
import { parseParamValue, TAKES_EFFECT_LABELS } from "./paramInput";

interface Props {
  node: number;
  param: Param;
  onWritten: (result: ParamWriteResult) => void;
}

function choiceText(param: Param, value: number | null | undefined): string {
  if (value == null) return "—";
  const label = param.choices[String(value)];
  return label ? `${value} · ${label}` : String(value);
}

/** One catalogue parameter: its value editable in place, the server's answer beside it. */
export const ParamRow = memo(function ParamRow({ node, param, onWritten }: Props): ReactNode {
  const { t } = useTranslation();
  const inputId = useId();
  const configure = useMay("configure");
  const why = configure.because(t("params.row.gate"));
  const [text, setText] = useState<string | null>(null);
  const [inputError, setInputError] = useState<string | null>(null);
  const [message, setMessage] = useState<string | null>(null);
  const write = useAction(async (value: number) => {
    const result = await call(
      api.PUT("/api/nodes/{node}/params/{name}", {
        params: { path: { node, name: param.name } },
        body: { value },
      }),
    );
    setMessage(result.message);
    setText(null);
    onWritten(result);
  });
  const choices = Object.entries(param.choices);
  const shown = text ?? (param.value == null ? "" : String(param.value));
  const dirty = text !== null && text !== String(param.value ?? "");

  function submit(event: SubmitEvent): void {
    event.preventDefault();
    // a new attempt replaces what the row said about the last one, success or failure
    setMessage(null);
    write.clearError();
    const parsed = parseParamValue(shown, param);
    if (!parsed.ok) {
      setInputError(parsed.error);
      return;
    }
    setInputError(null);
    void write.run(parsed.value);
  }

  // The control is named by the manual's parameter name alone ("PA-106"), which is what users
  // and tests look for; the label cell describes it.
  const label = param.name;
  const labelCellId = `${inputId}-label`;
  return (
    <>
      <tr className={message || inputError || write.error ? "has-note" : undefined}>
        <th scope="row" className="mono">
          {param.name}
        </th>
        <td id={labelCellId} title={param.description}>
          {param.label}
          <div className="muted small mono">{param.object}</div>
        </td>
        <td>
          <form className="param-editor" onSubmit={submit} noValidate>
            {choices.length > 0 ? (
              <select
                id={inputId}
                aria-label={label}
                aria-describedby={labelCellId}
                value={shown}
                disabled={!configure.allowed}
                title={why}
                onChange={(e) => setText(e.target.value)}
              >
                {param.value == null && <option value="">—</option>}
                {param.value != null && !(String(param.value) in param.choices) && (
                  <option value={String(param.value)}>
                    {t("params.row.notInList", { value: param.value })}
                  </option>
                )}
                {choices.map(([value, text]) => (
                  <option key={value} value={value}>
                    {value} · {text}
                  </option>
                ))}
              </select>
            ) : (
              <input
                id={inputId}
                className="narrow num"
                aria-label={label}
                aria-describedby={labelCellId}
                inputMode="numeric"
                value={shown}
                readOnly={!configure.allowed}
                title={why}
                aria-invalid={inputError !== null}
                onChange={(e) => {
                  setText(e.target.value);
                  setInputError(null);
                }}
              />
            )}
            <button
              type="submit"
              className="small"
              {...configure.gate(t("params.row.gate"), { disabled: write.busy || !dirty })}
              aria-label={t("params.row.writeNamed", { name: param.name })}
            >
              {t("params.row.write")}
            </button>
            {write.busy && <Spinner label={t("params.row.writing", { name: param.name })} />}
          </form>
          {param.error && <ErrorText error={param.error} />}
        </td>
        <td>{param.unit || "—"}</td>
        <td className="num small">
          {param.min}…{param.max}
        </td>
        <td className="num small default-cell" title={choiceText(param, param.default)}>
          {choices.length > 0 ? choiceText(param, param.default) : formatValue(param.default)}
        </td>
        <td>
          <span className={`badge effect-${param.takes_effect}`}>
            {t(TAKES_EFFECT_LABELS[param.takes_effect])}
          </span>
          {param.pending && (
            <span className="badge pending" title={t("params.row.pendingTitle")}>
              {t("params.row.pending")}
            </span>
          )}
        </td>
      </tr>
      {(message || inputError || write.error) && (
        <tr className="note-row">
          <td colSpan={7}>
            {message && (
              <p className="note" role="status">
                {param.name}: {message}
              </p>
            )}
            <ErrorText error={inputError ?? write.error} />
          </td>
        </tr>
      )}
    </>
  );
});
