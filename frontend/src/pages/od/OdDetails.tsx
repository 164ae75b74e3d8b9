import { useId, useState, type SubmitEvent, type ReactNode } from "react";

import { api, call, odPath } from "../../api/client";
import type { OdEntry, SdoValue } from "../../api/types";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { type MessageKey, useTranslation } from "../../i18n";
import { typeClass } from "../../lib/dataTypes";
import { formatValue, odAddress } from "../../lib/format";
import { useAction } from "../../lib/useApi";
import { parseValue, rangeHint } from "../../lib/valueInput";
import { useMay } from "../../session/context";

const ACCESS_LABELS: Readonly<Record<string, MessageKey>> = {
  ro: "od.details.access.ro",
  wo: "od.details.access.wo",
  rw: "od.details.access.rw",
  rwr: "od.details.access.rwr",
  rww: "od.details.access.rww",
  const: "od.details.access.const",
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
  const { t } = useTranslation();
  return (
    <dl className="facts read-result" aria-label={t("od.details.valueRead")}>
      <dt>{t("od.details.value")}</dt>
      <dd className="mono" data-testid="sdo-value">
        {formatValue(value.value)}
      </dd>
      <dt>{t("od.details.raw")}</dt>
      <dd className="mono">{value.raw_hex || "—"}</dd>
      <dt>{t("od.details.text")}</dt>
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
  const { t } = useTranslation();
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
  const accessKey = ACCESS_LABELS[entry.access];
  const placeholder =
    kind === "bytes"
      ? t("od.details.placeholder.bytes")
      : kind === "text"
        ? t("od.details.placeholder.text")
        : kind === "boolean"
          ? t("od.details.placeholder.boolean")
          : t("od.details.placeholder.number");

  return (
    <section className="card od-details" aria-labelledby="od-entry-heading">
      <header className="card-header">
        <h2 id="od-entry-heading">{entry.name}</h2>
        <span className="mono muted">{odAddress(entry.index, entry.subindex)}</span>
      </header>
      <dl className="facts">
        <dt>{t("od.details.dataType")}</dt>
        <dd className="mono">{entry.data_type_name}</dd>
        <dt>{t("od.details.accessLabel")}</dt>
        <dd>{accessKey ? t(accessKey) : entry.access}</dd>
        <dt>{t("od.details.pdoMappable")}</dt>
        <dd>{entry.pdo_mappable ? t("od.details.yes") : t("od.details.no")}</dd>
        <dt>{t("od.details.default")}</dt>
        <dd className="mono">{formatValue(entry.default)}</dd>
        <dt>{t("od.details.limits")}</dt>
        <dd className="mono">
          {entry.low != null || entry.high != null
            ? `${formatValue(entry.low)} … ${formatValue(entry.high)}`
            : "—"}
        </dd>
        <dt>{t("od.details.unit")}</dt>
        <dd>{entry.unit || "—"}</dd>
      </dl>
      {entry.description && <p className="description">{entry.description}</p>}

      {canRead(entry) && (
        <div className="button-row">
          <button type="button" disabled={read.busy} onClick={() => void read.run()}>
            {t("od.details.read")}
          </button>
          {read.busy && <Spinner label={t("od.details.reading")} />}
        </div>
      )}
      <ErrorText error={read.error} />
      {last && <ReadResult value={last} />}

      {canWrite(entry) || force ? (
        <form className="write-form" onSubmit={submit} noValidate>
          <label htmlFor={inputId}>{t("od.details.newValue")}</label>
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
              {...configure.gate(t("od.details.gateWrite"), { disabled: write.busy })}
            >
              {t("od.details.write")}
            </button>
            {write.busy && <Spinner label={t("od.details.writing")} />}
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
              {t("od.details.writeAnyway")}
            </button>
          )}
        </form>
      ) : (
        <p className="muted small">
          {entry.access === "const" ? t("od.details.constant") : t("od.details.readOnly")}{" "}
          <button type="button" className="link-button" onClick={() => setForce(true)}>
            {t("od.details.forceWrite")}
          </button>
        </p>
      )}
    </section>
  );
}
