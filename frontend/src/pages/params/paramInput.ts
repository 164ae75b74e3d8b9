// Parameters are integers with a catalogue range (and sometimes a list of choices); checked
// here before anything is sent so the user sees the reason at once.
import type { Param } from "../../api/types";
import { i18n, type MessageKey } from "../../i18n";

export type ParsedParam = { ok: true; value: number } | { ok: false; error: string };

const INTEGER = /^([+-]?)(0[xX][0-9A-Fa-f]+|[0-9]+)$/;

export function parseParamValue(
  text: string,
  param: Pick<Param, "min" | "max" | "choices">,
): ParsedParam {
  const trimmed = text.trim();
  const match = INTEGER.exec(trimmed);
  if (!match) {
    return {
      ok: false,
      error: i18n.t("params.input.wholeNumber", { min: param.min, max: param.max }),
    };
  }
  const magnitude = Number(match[2]);
  const value = match[1] === "-" ? -magnitude : magnitude;
  if (value < param.min || value > param.max) {
    return {
      ok: false,
      error: i18n.t("params.input.outside", { value, min: param.min, max: param.max }),
    };
  }
  const choices = Object.keys(param.choices);
  if (choices.length > 0 && !choices.includes(String(value))) {
    return { ok: false, error: i18n.t("params.input.notAllowed", { value }) };
  }
  return { ok: true, value };
}

/** When a written value takes effect: catalogue keys, turned into text where shown. */
export const TAKES_EFFECT_LABELS: Readonly<Record<Param["takes_effect"], MessageKey>> = {
  immediately: "params.takesEffect.immediately",
  after_reset: "params.takesEffect.after_reset",
  after_store_and_reset: "params.takesEffect.after_store_and_reset",
};
