// The Connect form's "options" box: one key=value per line, passed to python-can as extra
// bus arguments (docs/api.md BusConfig.options). Values that look like numbers or booleans
// are sent as such, because python-can interfaces expect e.g. an int port, not "29536".

import { i18n } from "../../i18n";

export type OptionValue = string | number | boolean;

export type ParsedOptions =
  { ok: true; options: Record<string, OptionValue> } | { ok: false; error: string };

function convert(raw: string): OptionValue {
  const text = raw.trim();
  if (/^(true|false)$/i.test(text)) return text.toLowerCase() === "true";
  if (/^[+-]?\d+$/.test(text)) return Number.parseInt(text, 10);
  if (/^0x[0-9a-f]+$/i.test(text)) return Number.parseInt(text.slice(2), 16);
  if (/^[+-]?(\d+\.\d*|\.\d+)([eE][+-]?\d+)?$/.test(text)) return Number(text);
  // Quotes keep a number-looking value a string: serial="0012"
  const quoted = /^"(.*)"$|^'(.*)'$/.exec(text);
  if (quoted) return quoted[1] ?? quoted[2] ?? "";
  return text;
}

export function parseBusOptions(text: string): ParsedOptions {
  const options: Record<string, OptionValue> = {};
  const lines = text.split(/\r?\n/);
  for (const [i, line] of lines.entries()) {
    const trimmed = line.trim();
    if (!trimmed || trimmed.startsWith("#")) continue;
    const eq = trimmed.indexOf("=");
    const key = eq > 0 ? trimmed.slice(0, eq).trim() : "";
    if (!/^[A-Za-z_][A-Za-z0-9_]*$/.test(key)) {
      return {
        ok: false,
        error: i18n.t("network.connect.badOption", { line: i + 1 }),
      };
    }
    options[key] = convert(trimmed.slice(eq + 1));
  }
  return { ok: true, options };
}

export function formatBusOptions(options: Record<string, unknown>): string {
  return Object.entries(options)
    .map(([key, value]) => `${key}=${String(value)}`)
    .join("\n");
}
