// The server's texts in the page's language. The API keeps its English `message`; a text the
// page can translate also carries `message_id` and `params` (docs/api.md, "Texts in the user's
// language"), looked up in the `server` catalogue. English, an id the catalogue does not know
// (a newer server) or none at all: the server's own words.
import { currentLanguage, i18n, type MessageKey } from "../i18n";

export type TextParams = Record<string, string | number>;

export interface ServerText {
  message: string;
  message_id?: string | null;
  params?: TextParams;
}

/** "pre-operational" → "preOperational": the catalogue's NMT keys. */
function camel(word: string): string {
  return word.replace(/-(\w)/g, (_, c: string) => c.toUpperCase());
}

/** A word the server sends as a parameter, in the page's language; unknown words as sent. */
function word(key: string, value: string): string {
  return i18n.t(key, { defaultValue: value });
}

/** "SDO response" → server.word.sdo_response: the server's fixed words (service names). */
const serverWordKey = (v: string): string =>
  `server.word.${v
    .toLowerCase()
    .replace(/[^a-z0-9]+/g, "_")
    .replace(/^_|_$/g, "")}`;
const stateKey = (v: string): string => `drive.state.${v.toLowerCase().replace(/ /g, "_")}`;
/** A CiA 402 state as the server names it ("Operation enabled") in the page's language. */
export function stateWords(state: string): string {
  return word(stateKey(state), state);
}

const nmtStateKey = (v: string): string => `nmt.state.${camel(v)}`;

// Parameters that are words of a fixed set (servodesk.events.texts): translated here; every
// other parameter (numbers, object addresses, names, a bus's own error text) shows as sent.
const PARAM_WORDS: Record<string, (value: string) => string> = {
  nmt_command: (v) => word(`nmt.command.${camel(v)}`, v),
  nmt_state: (v) => word(nmtStateKey(v), v),
  nmt: (v) => word(nmtStateKey(v), v),
  state: stateWords,
  was: stateWords,
  bus_state: (v) => word(`network.bus.state.${v}`, v),
  service: (v) => word(serverWordKey(v), v),
  use: (v) => word(serverWordKey(v), v),
  drive_command: (v) => word(`drive.command.${v.replace(/ /g, "_")}`, v),
};

/** An SDO abort's meaning by its code ("0x06020000"), in the page's language. */
export function abortMeaning(code: string, english: string): string {
  const hex = code.replace(/^0x/i, "").toUpperCase().padStart(8, "0");
  if (currentLanguage() === "en") return english;
  const key = `server.abort.${hex}`;
  return i18n.t(key, { defaultValue: english });
}

// Parameters that are texts of their own: a jog's stop reason inside "jog stopped (…)", who
// uses a CAN id inside a PDO problem
const NESTED = ["reason", "owner"] as const;

/** A text that names another carries that one's id as `<name>_id` and its parameters as
 * `<name>_<param>`: said in the page's language too; null when it has no id. */
function nested(params: TextParams, name: string): string | null {
  const id = params[`${name}_id`];
  if (typeof id !== "string") return null;
  const prefix = `${name}_`;
  const inner: TextParams = {};
  for (const [param, value] of Object.entries(params)) {
    if (param.startsWith(prefix) && param !== `${name}_id`)
      inner[param.slice(prefix.length)] = value;
  }
  const key = `server.${id}`;
  return i18n.t(key, { ...localParams(inner), defaultValue: String(params[name] ?? "") });
}

function localParams(params: TextParams): TextParams {
  const local: TextParams = {};
  for (const [name, value] of Object.entries(params)) {
    const translate = PARAM_WORDS[name];
    local[name] = translate && typeof value === "string" ? translate(value) : value;
  }
  if (typeof params.abort_code === "string" && typeof params.meaning === "string") {
    local.meaning = abortMeaning(params.abort_code, params.meaning);
  }
  for (const name of NESTED) {
    const text = nested(params, name);
    if (text !== null) local[name] = text;
  }
  return local;
}

/** `text` in the page's language; `overrides` replace parameters the page words itself (a
 * fault's name from the fault it carries). */
export function serverText(text: ServerText, overrides: TextParams = {}): string {
  if (currentLanguage() === "en" || !text.message_id) return text.message;
  const key = `server.${text.message_id}` as MessageKey;
  const params = { ...localParams(text.params ?? {}), ...overrides };
  return i18n.t(key, { ...params, defaultValue: text.message });
}
