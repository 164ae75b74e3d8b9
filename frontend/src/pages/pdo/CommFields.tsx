import { useId, useState, type ReactNode } from "react";

import { type MessageKey, useTranslation } from "../../i18n";
import {
  fixedCobIdReason,
  formatCobId,
  inhibitFromMs,
  inhibitMs,
  parseCobId,
  pdoLabel,
  problemText,
  transmissionWords,
  type CommField,
  type FitRules,
} from "./model";
import type { Pdo, Problem } from "./types";

/** The transmission type in words: the server's own when it sends them. */
export function pdoWords(pdo: Pdo): string {
  return pdo.transmission || transmissionWords(pdo.transmission_type, pdo.kind);
}

/** The communication parameter (14xxh / 18xxh) as read. */
export function CommFacts({ pdo }: { pdo: Pdo }): ReactNode {
  const { t } = useTranslation();
  return (
    <dl className="pdo-facts">
      <div>
        <dt>COB-ID</dt>
        <dd className="mono">{formatCobId(pdo.cob_id)}</dd>
      </div>
      <div>
        <dt>{t("pdo.comm.transmission")}</dt>
        <dd>
          {pdoWords(pdo)}{" "}
          <span className="muted small">
            {t("pdo.comm.typeNumber", { type: pdo.transmission_type })}
          </span>
        </dd>
      </div>
      <div>
        <dt>{t("pdo.comm.inhibitTime")}</dt>
        <dd>{inhibitMs(pdo.inhibit_time_100us)} ms</dd>
      </div>
      <div>
        <dt>{t("pdo.comm.eventTimer")}</dt>
        <dd>{pdo.event_timer_ms ? `${pdo.event_timer_ms} ms` : t("pdo.comm.off")}</dd>
      </div>
      {pdo.kind === "tpdo" && (
        <div>
          <dt>{t("pdo.comm.syncStart")}</dt>
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

/** Keys that would change an input's text. */
function isEdit(key: string): boolean {
  return key.length === 1 || key === "Backspace" || key === "Delete";
}

/** A text field that keeps what is typed and hands on only values that parse. A field the
 * drive fixes is read-only and says why when someone tries to change it. */
function Field({
  label,
  name,
  initial,
  parse,
  onValue,
  className = "tiny",
  title,
  problemId,
  hasProblem = false,
  fixed = null,
  onRefused,
}: {
  label: string;
  /** Accessible name, unique on the page ("TPDO1 COB-ID"). */
  name: string;
  initial: string;
  parse: (text: string) => number | null;
  onValue: (value: number) => void;
  className?: string;
  title?: string;
  /** The id of the server's problem with this field. */
  problemId?: string | undefined;
  hasProblem?: boolean;
  /** Why the drive does not let this field change; null when it does. */
  fixed?: string | null;
  /** Told the reason on a try to change a fixed field, and null when the field is left. */
  onRefused?: (reason: string | null) => void;
}): ReactNode {
  const { t } = useTranslation();
  const id = useId();
  const [text, setText] = useState(initial);
  return (
    <>
      <label htmlFor={id}>{label}</label>
      <input
        id={id}
        className={className}
        aria-label={name}
        aria-invalid={hasProblem || parse(text) === null}
        aria-describedby={problemId}
        inputMode="decimal"
        title={fixed ?? title}
        readOnly={fixed !== null}
        value={text}
        onKeyDown={(e) => {
          if (fixed !== null && isEdit(e.key)) onRefused?.(fixed);
        }}
        onPaste={() => {
          if (fixed !== null) onRefused?.(fixed);
        }}
        onBlur={() => {
          if (fixed !== null) onRefused?.(null);
        }}
        onChange={(e) => {
          setText(e.target.value);
          const value = parse(e.target.value);
          if (value !== null) onValue(value);
        }}
      />
      {fixed !== null && <span className="muted small">{t("pdo.comm.fixedByDrive")}</span>}
    </>
  );
}

const FIELD_LABELS: Readonly<Record<CommField, MessageKey | null>> = {
  cob_id: null, // "COB-ID" in every language
  transmission_type: "pdo.comm.transmissionType",
  inhibit_time: "pdo.comm.inhibitTime",
  event_timer: "pdo.comm.eventTimer",
  sync_start: "pdo.comm.syncStart",
};

/** The communication parameter as a draft's inputs (the card is keyed per draft, so the
 * fields start from the draft's values). The server's problems with a field mark it and are
 * written under the fields; a COB-ID the drive fixes cannot be edited. */
export function CommEditor({
  pdo,
  rules,
  problems,
  onChange,
}: {
  pdo: Pdo;
  rules: FitRules;
  problems: ReadonlyMap<CommField, readonly Problem[]>;
  onChange: (pdo: Pdo) => void;
}): ReactNode {
  const { t } = useTranslation();
  const id = useId();
  const label = pdoLabel(pdo);
  const [refused, setRefused] = useState<string | null>(null);
  const fieldLabel = (field: CommField): string => {
    const key = FIELD_LABELS[field];
    return key ? t(key) : "COB-ID";
  };
  const at = (field: CommField): { problemId?: string; hasProblem: boolean } =>
    problems.has(field) ? { problemId: `${id}-${field}`, hasProblem: true } : { hasProblem: false };
  return (
    <>
      <div className="pdo-edit-fields">
        <label className="check">
          <input
            type="checkbox"
            checked={pdo.valid}
            onChange={(e) => onChange({ ...pdo, valid: e.target.checked })}
          />
          {t("pdo.comm.valid")}
        </label>
        <Field
          label="COB-ID"
          name={t("pdo.comm.name.cobId", { label })}
          className="narrow mono"
          title={t("pdo.comm.cobIdTitle")}
          initial={formatCobId(pdo.cob_id)}
          parse={parseCobId}
          onValue={(cob_id) => onChange({ ...pdo, cob_id })}
          fixed={fixedCobIdReason(pdo, rules)}
          onRefused={setRefused}
          {...at("cob_id")}
        />
        <Field
          label={t("pdo.comm.transmissionType")}
          name={t("pdo.comm.name.transmissionType", { label })}
          initial={String(pdo.transmission_type)}
          parse={intIn(255)}
          onValue={(transmission_type) => onChange({ ...pdo, transmission_type })}
          {...at("transmission_type")}
        />
        <span className="muted small pdo-words">{pdoWords({ ...pdo, transmission: "" })}</span>
        <Field
          label={t("pdo.comm.inhibitMs")}
          name={t("pdo.comm.name.inhibitTime", { label })}
          initial={String(inhibitMs(pdo.inhibit_time_100us))}
          parse={msIn}
          onValue={(inhibit_time_100us) => onChange({ ...pdo, inhibit_time_100us })}
          {...at("inhibit_time")}
        />
        <Field
          label={t("pdo.comm.eventTimerMs")}
          name={t("pdo.comm.name.eventTimer", { label })}
          initial={String(pdo.event_timer_ms)}
          parse={intIn(65535)}
          onValue={(event_timer_ms) => onChange({ ...pdo, event_timer_ms })}
          {...at("event_timer")}
        />
        {pdo.kind === "tpdo" && (
          <Field
            label={t("pdo.comm.syncStart")}
            name={t("pdo.comm.name.syncStart", { label })}
            initial={String(pdo.sync_start)}
            parse={intIn(240)}
            onValue={(sync_start) => onChange({ ...pdo, sync_start })}
            {...at("sync_start")}
          />
        )}
      </div>
      {refused && (
        <p className="error-text small" role="alert">
          {refused}
        </p>
      )}
      {problems.size > 0 && (
        <ul
          className="pdo-problems pdo-field-problems"
          aria-label={t("pdo.comm.parameterProblems", { label })}
        >
          {[...problems].map(([field, list]) => (
            <li key={field} id={`${id}-${field}`} className="error-text">
              <strong>{t("pdo.comm.fieldProblems", { field: fieldLabel(field) })}</strong>{" "}
              {list.map(problemText).join(" ")}
            </li>
          ))}
        </ul>
      )}
    </>
  );
}
