// Values read from a node, shown in the tree's value column (from "Upload all" or single
// reads). Entries are immutable so unchanged rows can skip re-rendering.
import type { JobResult, SdoValue } from "../../api/types";
import { formatAbortCode } from "../../api/errors";

export interface ShownValue {
  text: string;
  /** The read failed: text is the abort code and meaning. */
  failed: boolean;
}

export type ValueMap = Readonly<Record<string, ShownValue>>;

export function valueKey(index: number, subindex: number): string {
  return `${index}:${subindex}`;
}

export function fromRead(value: SdoValue): ShownValue {
  return { text: value.text, failed: false };
}

export function fromJobResult(result: JobResult): ShownValue {
  if (result.abort_code || result.message) {
    const code = result.abort_code ? `${formatAbortCode(result.abort_code)} ` : "";
    return { text: `${code}${result.message ?? ""}`.trim(), failed: true };
  }
  return { text: result.text ?? String(result.value ?? ""), failed: false };
}

/** Merge job results into the map, keeping entries whose text did not change. */
export function mergeResults(values: ValueMap, results: readonly JobResult[]): ValueMap {
  let next: Record<string, ShownValue> | null = null;
  for (const result of results) {
    const key = valueKey(result.index, result.subindex);
    const shown = fromJobResult(result);
    const old = values[key];
    if (old && old.text === shown.text && old.failed === shown.failed) continue;
    next ??= { ...values };
    next[key] = shown;
  }
  return next ?? values;
}
