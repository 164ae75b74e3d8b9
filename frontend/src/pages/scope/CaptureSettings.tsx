import { useId, type ReactNode } from "react";

import type { NodeInfo } from "../../api/types";
import { i18n, useTranslation, type MessageKey } from "../../i18n";
import { odAddress, profileLabel } from "../../lib/format";
import {
  CIA402_STATES,
  STATUSWORD,
  levelHint,
  signalKey,
  type ScopeForm,
  type SignalChoice,
  type TriggerForm,
} from "./model";
import type { CaptureSignal, Edge, TriggerKind } from "./types";

const KINDS: { kind: TriggerKind; label: MessageKey }[] = [
  { kind: "none", label: "scope.settings.kind.none" },
  { kind: "level", label: "scope.settings.kind.level" },
  { kind: "bit", label: "scope.settings.kind.bit" },
  { kind: "emcy", label: "scope.settings.kind.emcy" },
  { kind: "state", label: "scope.settings.kind.state" },
];

const EDGES: { edge: Edge; label: MessageKey }[] = [
  { edge: "rising", label: "scope.settings.edge.rising" },
  { edge: "falling", label: "scope.settings.edge.falling" },
  { edge: "either", label: "scope.settings.edge.either" },
];

function signalLabel(signal: SignalChoice): string {
  return i18n.t("scope.settings.signalOption", {
    node: signal.node,
    address: odAddress(signal.index, signal.subindex),
    name: signal.name,
  });
}

/** SYNC period, duration, name and the trigger. */
export function CaptureSettings({
  form,
  nodes,
  planned,
  onChange,
}: {
  form: ScopeForm;
  nodes: readonly NodeInfo[];
  /** The plan's signals (units and scale of the level trigger's signal). */
  planned: readonly CaptureSignal[];
  onChange: (form: ScopeForm) => void;
}): ReactNode {
  const { t } = useTranslation();
  const id = useId();
  const trigger = form.trigger;
  const setTrigger = (patch: Partial<TriggerForm>): void =>
    onChange({ ...form, trigger: { ...trigger, ...patch } });
  const firstNode = form.signals[0]?.node ?? nodes[0]?.node ?? null;

  const nodeSelect = (label: string, anyNode: boolean): ReactNode => (
    <>
      <label htmlFor={`${id}-tnode`}>{label}</label>
      <select
        id={`${id}-tnode`}
        value={trigger.node ?? ""}
        onChange={(e) =>
          setTrigger({ node: e.target.value === "" ? null : Number(e.target.value) })
        }
      >
        {(anyNode || trigger.node === null) && (
          <option value="">
            {anyNode ? t("scope.settings.anyNode") : t("scope.settings.chooseNode")}
          </option>
        )}
        {nodes.map((info) => (
          <option key={info.node} value={info.node}>
            {info.profile_label
              ? t("scope.settings.nodeOptionProfile", {
                  node: info.node,
                  profile: profileLabel(info),
                })
              : t("scope.settings.nodeOption", { node: info.node })}
          </option>
        ))}
      </select>
    </>
  );
  const edgeSelect = (
    <>
      <label htmlFor={`${id}-edge`}>{t("scope.settings.edgeLabel")}</label>
      <select
        id={`${id}-edge`}
        value={trigger.edge}
        onChange={(e) => setTrigger({ edge: e.target.value as Edge })}
      >
        {EDGES.map(({ edge, label }) => (
          <option key={edge} value={edge}>
            {t(label)}
          </option>
        ))}
      </select>
    </>
  );
  const watched = planned.find((s) => signalKey(s) === trigger.signal);
  const bitObjects = form.signals.filter(
    (s) => s.node === trigger.node && !(s.index === STATUSWORD && s.subindex === 0),
  );

  return (
    <section className="card scope-settings" aria-labelledby={`${id}-h`}>
      <header className="card-header">
        <h2 id={`${id}-h`}>{t("scope.settings.heading")}</h2>
      </header>
      <div className="scope-fields">
        <label htmlFor={`${id}-sync`}>{t("scope.settings.sync")}</label>
        <span className="inline">
          <input
            id={`${id}-sync`}
            className="narrow"
            type="number"
            min={500}
            step={100}
            value={form.syncPeriodUs}
            onChange={(e) => onChange({ ...form, syncPeriodUs: e.target.value })}
          />
          <span>µs</span>
          <span className="muted small">{t("scope.settings.syncHint")}</span>
        </span>
        <label htmlFor={`${id}-duration`}>{t("scope.settings.duration")}</label>
        <span className="inline">
          <input
            id={`${id}-duration`}
            className="narrow"
            type="number"
            min={0.1}
            step={0.5}
            value={form.durationS}
            onChange={(e) => onChange({ ...form, durationS: e.target.value })}
          />
          <span>s</span>
        </span>
        <label htmlFor={`${id}-name`}>{t("scope.settings.name")}</label>
        <input
          id={`${id}-name`}
          maxLength={80}
          placeholder={t("scope.settings.namePlaceholder")}
          value={form.name}
          onChange={(e) => onChange({ ...form, name: e.target.value })}
        />
      </div>
      <fieldset className="scope-trigger">
        <legend>{t("scope.settings.trigger")}</legend>
        <div className="scope-fields">
          <label htmlFor={`${id}-kind`}>{t("scope.settings.startOn")}</label>
          <select
            id={`${id}-kind`}
            value={trigger.kind}
            onChange={(e) => {
              const kind = e.target.value as TriggerKind;
              const node = kind === "emcy" ? null : (trigger.node ?? firstNode);
              const signal = trigger.signal || (form.signals[0] ? signalKey(form.signals[0]) : "");
              setTrigger({ kind, node, signal });
            }}
          >
            {KINDS.map(({ kind, label }) => (
              <option key={kind} value={kind}>
                {t(label)}
              </option>
            ))}
          </select>
          {trigger.kind === "level" && (
            <>
              <label htmlFor={`${id}-signal`}>{t("scope.settings.signal")}</label>
              <select
                id={`${id}-signal`}
                value={trigger.signal}
                onChange={(e) => setTrigger({ signal: e.target.value })}
              >
                {trigger.signal === "" && (
                  <option value="">{t("scope.settings.chooseSignal")}</option>
                )}
                {form.signals.map((signal) => (
                  <option key={signalKey(signal)} value={signalKey(signal)}>
                    {signalLabel(signal)}
                  </option>
                ))}
              </select>
              <label htmlFor={`${id}-level`}>{t("scope.settings.level")}</label>
              <span className="inline">
                <input
                  id={`${id}-level`}
                  className="narrow"
                  type="number"
                  value={trigger.level}
                  onChange={(e) => setTrigger({ level: e.target.value })}
                />
                <span className="muted small">
                  {levelHint(trigger.level, watched) ?? t("scope.settings.levelRaw")}
                </span>
              </span>
              {edgeSelect}
            </>
          )}
          {trigger.kind === "bit" && (
            <>
              {nodeSelect(t("scope.settings.node"), false)}
              <label htmlFor={`${id}-object`}>{t("scope.settings.object")}</label>
              <select
                id={`${id}-object`}
                value={trigger.bitObject}
                onChange={(e) => setTrigger({ bitObject: e.target.value })}
              >
                <option value="">{t("scope.settings.statusword")}</option>
                {bitObjects.map((signal) => (
                  <option key={signalKey(signal)} value={`${signal.index}:${signal.subindex}`}>
                    {odAddress(signal.index, signal.subindex)} {signal.name}
                  </option>
                ))}
              </select>
              <label htmlFor={`${id}-bit`}>{t("scope.settings.bit")}</label>
              <input
                id={`${id}-bit`}
                className="narrow"
                type="number"
                min={0}
                max={63}
                value={trigger.bit}
                onChange={(e) => setTrigger({ bit: e.target.value })}
              />
              {edgeSelect}
            </>
          )}
          {trigger.kind === "emcy" && nodeSelect(t("scope.settings.from"), true)}
          {trigger.kind === "state" && (
            <>
              {nodeSelect(t("scope.settings.node"), false)}
              <label htmlFor={`${id}-state`}>{t("scope.settings.state")}</label>
              <select
                id={`${id}-state`}
                value={trigger.state}
                onChange={(e) => setTrigger({ state: e.target.value })}
              >
                <option value="">{t("scope.settings.anyState")}</option>
                {CIA402_STATES.map((state) => (
                  <option key={state} value={state}>
                    {t("scope.settings.enters", { state })}
                  </option>
                ))}
              </select>
            </>
          )}
          {trigger.kind !== "none" && (
            <>
              <label htmlFor={`${id}-pre`}>{t("scope.settings.pre")}</label>
              <span className="inline">
                <input
                  id={`${id}-pre`}
                  className="narrow"
                  type="number"
                  min={0}
                  step={0.1}
                  value={trigger.preS}
                  onChange={(e) => setTrigger({ preS: e.target.value })}
                />
                <span>s</span>
                <span className="muted small">{t("scope.settings.preHint")}</span>
              </span>
              <span>{t("scope.settings.mode")}</span>
              <span className="inline" role="radiogroup" aria-label={t("scope.settings.modeLabel")}>
                <label className="check">
                  <input
                    type="radio"
                    name={`${id}-mode`}
                    checked={trigger.mode === "single"}
                    onChange={() => setTrigger({ mode: "single" })}
                  />
                  {t("scope.settings.single")}
                </label>
                <label className="check">
                  <input
                    type="radio"
                    name={`${id}-mode`}
                    checked={trigger.mode === "normal"}
                    onChange={() => setTrigger({ mode: "normal" })}
                  />
                  {t("scope.settings.normal")}
                </label>
                {trigger.mode === "normal" && (
                  <label className="check">
                    {t("scope.settings.keepLast")}
                    <input
                      className="tiny"
                      type="number"
                      min={1}
                      max={100}
                      aria-label={t("scope.settings.keptLabel")}
                      value={trigger.keep}
                      onChange={(e) => setTrigger({ keep: e.target.value })}
                    />
                  </label>
                )}
              </span>
            </>
          )}
        </div>
      </fieldset>
    </section>
  );
}
