import { useId, useState, type SubmitEvent, type ReactNode } from "react";

import { api, call, odPath } from "../../api/client";
import type { OdEntry, SdoValue } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { typeClass } from "../../lib/dataTypes";
import { formatValue, odAddress } from "../../lib/format";
import { useAction } from "../../lib/useApi";
import { parseValue, rangeHint } from "../../lib/valueInput";
import { useMay } from "../../session/context";

const ACCESS_LABELS: Readonly<Record<string, string>> = {
  ro: "read only",
  wo: "write only",
  rw: "read / write",
  rwr: "read / write (TPDO)",
  rww: "read / write (RPDO)",
  const: "constant",
};

export function canRead(entry: OdEntry): boolean {
  return entry.access !== "wo";
}

export function canWrite(entry: OdEntry): boolean {
  return (
    entry.access === "rw" ||
    entry.access === "wo" ||
    entry.access === "rwr" ||
    entry.access === "rww"
  );
}

function ReadResult({ value }: { value: SdoValue }): ReactNode {
  return (
    <dl className="facts read-result" aria-label="Value read">
      <dt>Value</dt>
      <dd className="mono" data-testid="sdo-value">
        {formatValue(value.value)}
      </dd>
      <dt>Raw</dt>
      <dd className="mono">{value.raw_hex || "—"}</dd>
      <dt>Text</dt>
      <dd className="mono">{value.text}</dd>
    </dl>
  );
}

interface Props {
  node: number;
  entry: OdEntry;
  onValue: (value: SdoValue) => void;
}

/** One entry: what the dictionary says about it, and read / write against the device. */
export function OdDetails({ node, entry, onValue }: Props): ReactNode {
  const inputId = useId();
  const configure = useMay("configure");
  const [last, setLast] = useState<SdoValue | null>(null);
  const [text, setText] = useState("");
  const [inputError, setInputError] = useState<string | null>(null);
  // An EDS can be wrong about the firmware: an expert may send the write anyway and see what
  // the drive answers (typically abort 06010002).
  const [force, setForce] = useState(false);
  const path = { node, ...odPath(entry.index, entry.subindex) };

  const read = useAction(async () => {
    const value = await call(
      api.GET("/api/nodes/{node}/sdo/{index}/{subindex}", { params: { path } }),
    );
    setLast(value);
    onValue(value);
  });
  // confirm: a write the server asked about first (a heartbeat time below 10 ms, 1017h)
  const write = useAction(async (value: number | string, confirm: boolean) => {
    const readBack = await call(
      api.PUT("/api/nodes/{node}/sdo/{index}/{subindex}", {
        params: { path },
        body: { value, confirm },
      }),
    );
    setLast(readBack);
    onValue(readBack);
  });

  function submit(event: SubmitEvent): void {
    event.preventDefault();
    const parsed = parseValue(text, entry);
    if (!parsed.ok) {
      setInputError(parsed.error);
      return;
    }
    setInputError(null);
    void write.run(parsed.value, false);
  }

  function confirmWrite(): void {
    const parsed = parseValue(text, entry);
    if (parsed.ok) void write.run(parsed.value, true);
  }
  const needsConfirm = inputError === null && write.error?.kind === "confirmation_required";

  const kind = typeClass(entry.data_type_name);
  const hint = rangeHint(entry);
  const placeholder =
    kind === "bytes"
      ? "hex bytes, e.g. 01 02 0A"
      : kind === "text"
        ? "text"
        : kind === "boolean"
          ? "0 or 1"
          : "decimal or 0x hex";

  return (
    <section className="card od-details" aria-labelledby="od-entry-heading">
      <header className="card-header">
        <h2 id="od-entry-heading">{entry.name}</h2>
        <span className="mono muted">{odAddress(entry.index, entry.subindex)}</span>
      </header>
      <dl className="facts">
        <dt>Data type</dt>
        <dd className="mono">{entry.data_type_name}</dd>
        <dt>Access</dt>
        <dd>{ACCESS_LABELS[entry.access] ?? entry.access}</dd>
        <dt>PDO mappable</dt>
        <dd>{entry.pdo_mappable ? "yes" : "no"}</dd>
        <dt>Default</dt>
        <dd className="mono">{formatValue(entry.default)}</dd>
        <dt>Limits</dt>
        <dd className="mono">
          {entry.low != null || entry.high != null
            ? `${formatValue(entry.low)} … ${formatValue(entry.high)}`
            : "—"}
        </dd>
        <dt>Unit</dt>
        <dd>{entry.unit || "—"}</dd>
      </dl>
      {entry.description && <p className="description">{entry.description}</p>}

      {canRead(entry) && (
        <div className="button-row">
          <button type="button" disabled={read.busy} onClick={() => void read.run()}>
            Read
          </button>
          {read.busy && <Spinner label="Reading" />}
        </div>
      )}
      <ErrorText error={read.error} />
      {last && <ReadResult value={last} />}

      {canWrite(entry) || force ? (
        <form className="write-form" onSubmit={submit} noValidate>
          <label htmlFor={inputId}>New value</label>
          <div className="inline">
            <input
              id={inputId}
              className={kind === "text" || kind === "bytes" ? "wide" : "mono"}
              inputMode={kind === "integer" || kind === "boolean" ? "text" : undefined}
              value={text}
              placeholder={placeholder}
              aria-invalid={inputError !== null}
              aria-describedby={`${inputId}-hint`}
              onChange={(e) => {
                setText(e.target.value);
                setInputError(null);
              }}
            />
            <button
              type="submit"
              className="primary"
              {...configure.gate("write to the object dictionary", { disabled: write.busy })}
            >
              Write
            </button>
            {write.busy && <Spinner label="Writing" />}
          </div>
          <p id={`${inputId}-hint`} className="muted small">
            {entry.data_type_name}
            {hint && ` · ${hint}`}
          </p>
          <ErrorText error={inputError ?? write.error} />
          {needsConfirm && (
            <button
              type="button"
              className="small danger"
              disabled={write.busy || !configure.allowed}
              onClick={confirmWrite}
            >
              Write anyway
            </button>
          )}
        </form>
      ) : (
        <p className="muted small">
          {entry.access === "const" ? "Constant" : "Read-only"} in the dictionary.{" "}
          <button type="button" className="link-button" onClick={() => setForce(true)}>
            Write anyway…
          </button>
        </p>
      )}
    </section>
  );
}
