import { useId, useState, type ReactNode } from "react";

import {
  formatCobId,
  inhibitFromMs,
  inhibitMs,
  parseCobId,
  pdoLabel,
  transmissionWords,
} from "./model";
import type { Pdo } from "./types";

/** The transmission type in words: the server's own when it sends them. */
export function pdoWords(pdo: Pdo): string {
  return pdo.transmission || transmissionWords(pdo.transmission_type, pdo.kind);
}

/** The communication parameter (14xxh / 18xxh) as read. */
export function CommFacts({ pdo }: { pdo: Pdo }): ReactNode {
  return (
    <dl className="pdo-facts">
      <div>
        <dt>COB-ID</dt>
        <dd className="mono">{formatCobId(pdo.cob_id)}</dd>
      </div>
      <div>
        <dt>Transmission</dt>
        <dd>
          {pdoWords(pdo)} <span className="muted small">(type {pdo.transmission_type})</span>
        </dd>
      </div>
      <div>
        <dt>Inhibit time</dt>
        <dd>{inhibitMs(pdo.inhibit_time_100us)} ms</dd>
      </div>
      <div>
        <dt>Event timer</dt>
        <dd>{pdo.event_timer_ms ? `${pdo.event_timer_ms} ms` : "off"}</dd>
      </div>
      {pdo.kind === "tpdo" && (
        <div>
          <dt>SYNC start</dt>
          <dd>{pdo.sync_start || "—"}</dd>
        </div>
      )}
    </dl>
  );
}

function intIn(max: number): (text: string) => number | null {
  return (text) => {
    if (!/^\d+$/.test(text.trim())) return null;
    const value = Number(text);
    return value <= max ? value : null;
  };
}

function msIn(text: string): number | null {
  if (!/^\d+(\.\d)?$/.test(text.trim())) return null;
  const ms = Number(text);
  return ms <= 6553.5 ? inhibitFromMs(ms) : null;
}

/** A text field that keeps what is typed and hands on only values that parse. */
function Field({
  label,
  name,
  initial,
  parse,
  onValue,
  className = "tiny",
  title,
}: {
  label: string;
  /** Accessible name, unique on the page ("TPDO1 COB-ID"). */
  name: string;
  initial: string;
  parse: (text: string) => number | null;
  onValue: (value: number) => void;
  className?: string;
  title?: string;
}): ReactNode {
  const id = useId();
  const [text, setText] = useState(initial);
  return (
    <>
      <label htmlFor={id}>{label}</label>
      <input
        id={id}
        className={className}
        aria-label={name}
        aria-invalid={parse(text) === null}
        inputMode="decimal"
        title={title}
        value={text}
        onChange={(e) => {
          setText(e.target.value);
          const value = parse(e.target.value);
          if (value !== null) onValue(value);
        }}
      />
    </>
  );
}

/** The communication parameter as a draft's inputs (the card is keyed per draft, so the
 * fields start from the draft's values). */
export function CommEditor({
  pdo,
  onChange,
}: {
  pdo: Pdo;
  onChange: (pdo: Pdo) => void;
}): ReactNode {
  const label = pdoLabel(pdo);
  return (
    <div className="pdo-edit-fields">
      <label className="check">
        <input
          type="checkbox"
          checked={pdo.valid}
          onChange={(e) => onChange({ ...pdo, valid: e.target.checked })}
        />
        Valid
      </label>
      <Field
        label="COB-ID"
        name={`${label} COB-ID`}
        className="narrow mono"
        title="CAN identifier in hex, 001h–7FFh"
        initial={formatCobId(pdo.cob_id)}
        parse={parseCobId}
        onValue={(cob_id) => onChange({ ...pdo, cob_id })}
      />
      <Field
        label="Transmission type"
        name={`${label} transmission type`}
        initial={String(pdo.transmission_type)}
        parse={intIn(255)}
        onValue={(transmission_type) => onChange({ ...pdo, transmission_type })}
      />
      <span className="muted small pdo-words">{pdoWords({ ...pdo, transmission: "" })}</span>
      <Field
        label="Inhibit ms"
        name={`${label} inhibit time ms`}
        initial={String(inhibitMs(pdo.inhibit_time_100us))}
        parse={msIn}
        onValue={(inhibit_time_100us) => onChange({ ...pdo, inhibit_time_100us })}
      />
      <Field
        label="Event timer ms"
        name={`${label} event timer ms`}
        initial={String(pdo.event_timer_ms)}
        parse={intIn(65535)}
        onValue={(event_timer_ms) => onChange({ ...pdo, event_timer_ms })}
      />
      {pdo.kind === "tpdo" && (
        <Field
          label="SYNC start"
          name={`${label} SYNC start`}
          initial={String(pdo.sync_start)}
          parse={intIn(240)}
          onValue={(sync_start) => onChange({ ...pdo, sync_start })}
        />
      )}
    </div>
  );
}
