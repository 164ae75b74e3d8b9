// The Scope form survives leaving the page (and a reload) in this tab's session storage: a
// failed start or a look at another page never loses the selection.
import {
  DEFAULT_FORM,
  DEFAULT_TRIGGER,
  MAX_SIGNALS,
  type ScopeForm,
  type SignalChoice,
} from "./model";

const KEY = "servodesk.scope.form";

function isRecord(value: unknown): value is Record<string, unknown> {
  return typeof value === "object" && value !== null && !Array.isArray(value);
}

function isSignal(value: unknown): value is SignalChoice {
  return (
    isRecord(value) &&
    Number.isInteger(value.node) &&
    Number.isInteger(value.index) &&
    Number.isInteger(value.subindex) &&
    typeof value.name === "string"
  );
}

const text = (value: unknown, fallback: string): string =>
  typeof value === "string" ? value : fallback;

/** A stored form back, every field checked; anything unreadable falls back to the default. */
export function parseForm(stored: string | null): ScopeForm {
  let data: unknown;
  try {
    data = stored ? JSON.parse(stored) : null;
  } catch {
    return DEFAULT_FORM;
  }
  if (!isRecord(data)) return DEFAULT_FORM;
  const signals = Array.isArray(data.signals)
    ? data.signals.filter(isSignal).slice(0, MAX_SIGNALS)
    : [];
  const trigger = isRecord(data.trigger) ? data.trigger : {};
  const kinds = ["none", "level", "bit", "emcy", "state"] as const;
  const edges = ["rising", "falling", "either"] as const;
  const kind = kinds.find((k) => k === trigger.kind) ?? DEFAULT_TRIGGER.kind;
  const edge = edges.find((e) => e === trigger.edge) ?? DEFAULT_TRIGGER.edge;
  return {
    signals,
    syncPeriodUs: text(data.syncPeriodUs, DEFAULT_FORM.syncPeriodUs),
    durationS: text(data.durationS, DEFAULT_FORM.durationS),
    name: text(data.name, ""),
    trigger: {
      kind,
      node: Number.isInteger(trigger.node) ? (trigger.node as number) : null,
      signal: text(trigger.signal, ""),
      bitObject: text(trigger.bitObject, ""),
      level: text(trigger.level, ""),
      edge,
      bit: text(trigger.bit, ""),
      state: text(trigger.state, ""),
      preS: text(trigger.preS, DEFAULT_TRIGGER.preS),
      mode: trigger.mode === "normal" ? "normal" : "single",
      keep: text(trigger.keep, DEFAULT_TRIGGER.keep),
    },
  };
}

export function loadForm(): ScopeForm {
  try {
    return parseForm(window.sessionStorage.getItem(KEY));
  } catch {
    return DEFAULT_FORM; // storage blocked
  }
}

export function saveForm(form: ScopeForm): void {
  try {
    window.sessionStorage.setItem(KEY, JSON.stringify(form));
  } catch {
    // storage blocked or full: the form just does not survive a reload
  }
}
