import { useId, type ReactNode } from "react";

import type { NodeInfo } from "../../api/types";
import { odAddress } from "../../lib/format";
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

const KINDS: { kind: TriggerKind; label: string }[] = [
  { kind: "none", label: "None: record at once" },
  { kind: "level", label: "Level of a signal" },
  { kind: "bit", label: "Bit of an object" },
  { kind: "emcy", label: "EMCY (a drive's fault)" },
  { kind: "state", label: "CiA 402 state" },
];

const EDGES: { edge: Edge; label: string }[] = [
  { edge: "rising", label: "Rising" },
  { edge: "falling", label: "Falling" },
  { edge: "either", label: "Either" },
];

function signalLabel(signal: SignalChoice): string {
  return `node ${signal.node} · ${odAddress(signal.index, signal.subindex)} ${signal.name}`;
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
          <option value="">{anyNode ? "Any node" : "Choose a node"}</option>
        )}
        {nodes.map((info) => (
          <option key={info.node} value={info.node}>
            Node {info.node}
            {info.profile_label ? ` · ${info.profile_label}` : ""}
          </option>
        ))}
      </select>
    </>
  );
  const edgeSelect = (
    <>
      <label htmlFor={`${id}-edge`}>Edge</label>
      <select
        id={`${id}-edge`}
        value={trigger.edge}
        onChange={(e) => setTrigger({ edge: e.target.value as Edge })}
      >
        {EDGES.map(({ edge, label }) => (
          <option key={edge} value={edge}>
            {label}
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
        <h2 id={`${id}-h`}>Capture</h2>
      </header>
      <div className="scope-fields">
        <label htmlFor={`${id}-sync`}>SYNC period</label>
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
          <span className="muted small">
            one sample per SYNC; at least 500 µs, 1 ms or more advised (MDi-S1-C CANopen manual
            §2.6)
          </span>
        </span>
        <label htmlFor={`${id}-duration`}>Duration</label>
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
        <label htmlFor={`${id}-name`}>Name</label>
        <input
          id={`${id}-name`}
          maxLength={80}
          placeholder="optional, e.g. axis 1 tuning"
          value={form.name}
          onChange={(e) => onChange({ ...form, name: e.target.value })}
        />
      </div>
      <fieldset className="scope-trigger">
        <legend>Trigger</legend>
        <div className="scope-fields">
          <label htmlFor={`${id}-kind`}>Start on</label>
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
                {label}
              </option>
            ))}
          </select>
          {trigger.kind === "level" && (
            <>
              <label htmlFor={`${id}-signal`}>Signal</label>
              <select
                id={`${id}-signal`}
                value={trigger.signal}
                onChange={(e) => setTrigger({ signal: e.target.value })}
              >
                {trigger.signal === "" && <option value="">Choose a signal</option>}
                {form.signals.map((signal) => (
                  <option key={signalKey(signal)} value={signalKey(signal)}>
                    {signalLabel(signal)}
                  </option>
                ))}
              </select>
              <label htmlFor={`${id}-level`}>Level</label>
              <span className="inline">
                <input
                  id={`${id}-level`}
                  className="narrow"
                  type="number"
                  value={trigger.level}
                  onChange={(e) => setTrigger({ level: e.target.value })}
                />
                <span className="muted small">
                  {levelHint(trigger.level, watched) ?? "raw value, in the object's own units"}
                </span>
              </span>
              {edgeSelect}
            </>
          )}
          {trigger.kind === "bit" && (
            <>
              {nodeSelect("Node", false)}
              <label htmlFor={`${id}-object`}>Object</label>
              <select
                id={`${id}-object`}
                value={trigger.bitObject}
                onChange={(e) => setTrigger({ bitObject: e.target.value })}
              >
                <option value="">6041h Statusword</option>
                {bitObjects.map((signal) => (
                  <option key={signalKey(signal)} value={`${signal.index}:${signal.subindex}`}>
                    {odAddress(signal.index, signal.subindex)} {signal.name}
                  </option>
                ))}
              </select>
              <label htmlFor={`${id}-bit`}>Bit</label>
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
          {trigger.kind === "emcy" && nodeSelect("From", true)}
          {trigger.kind === "state" && (
            <>
              {nodeSelect("Node", false)}
              <label htmlFor={`${id}-state`}>State</label>
              <select
                id={`${id}-state`}
                value={trigger.state}
                onChange={(e) => setTrigger({ state: e.target.value })}
              >
                <option value="">Any change of state</option>
                {CIA402_STATES.map((state) => (
                  <option key={state} value={state}>
                    Enters {state}
                  </option>
                ))}
              </select>
            </>
          )}
          {trigger.kind !== "none" && (
            <>
              <label htmlFor={`${id}-pre`}>Pre-trigger</label>
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
                <span className="muted small">of the duration recorded before the trigger</span>
              </span>
              <span>Mode</span>
              <span className="inline" role="radiogroup" aria-label="Trigger mode">
                <label className="check">
                  <input
                    type="radio"
                    name={`${id}-mode`}
                    checked={trigger.mode === "single"}
                    onChange={() => setTrigger({ mode: "single" })}
                  />
                  Single
                </label>
                <label className="check">
                  <input
                    type="radio"
                    name={`${id}-mode`}
                    checked={trigger.mode === "normal"}
                    onChange={() => setTrigger({ mode: "normal" })}
                  />
                  Normal: re-arm after each capture
                </label>
                {trigger.mode === "normal" && (
                  <label className="check">
                    keep the last
                    <input
                      className="tiny"
                      type="number"
                      min={1}
                      max={100}
                      aria-label="Captures kept"
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
