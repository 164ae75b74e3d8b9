// How an audit entry reads in the table and the undo dialog.
import { formatAbortCode } from "../../api/errors";
import { i18n, type MessageKey } from "../../i18n";
import { odAddress } from "../../lib/format";
import type { AuditEntry } from "./types";

/** "2025-05-01 14:30:12" in the browser's time zone. */
export function formatDateTime(unixSeconds: number): string {
  const d = new Date(unixSeconds * 1000);
  const pad = (n: number): string => String(n).padStart(2, "0");
  return `${d.getFullYear()}-${pad(d.getMonth() + 1)}-${pad(d.getDate())} ${pad(d.getHours())}:${pad(d.getMinutes())}:${pad(d.getSeconds())}`;
}

/** "6081h:00", or "" for entries that touch no single object (NMT, enable …). */
export function objectText(entry: Pick<AuditEntry, "index" | "subindex">): string {
  if (entry.index === null) return "";
  return odAddress(entry.index, entry.subindex ?? 0);
}

export function valueText(value: AuditEntry["old"]): string {
  if (value === null) return "—";
  return typeof value === "string" ? `"${value}"` : String(value);
}

/** "1000 → 2000"; "" when the entry changed no value. */
export function changeText(entry: Pick<AuditEntry, "old" | "new">): string {
  if (entry.old === null && entry.new === null) return "";
  return `${valueText(entry.old)} → ${valueText(entry.new)}`;
}

const RESULT_LABEL: Record<AuditEntry["result"], MessageKey> = {
  ok: "logs.audit.result.ok",
  failed: "logs.audit.result.failed",
  pending: "logs.audit.result.pending",
  unknown: "logs.audit.result.unknown",
};

export function resultLabel(result: AuditEntry["result"]): string {
  return i18n.t(RESULT_LABEL[result]);
}

/** "0x06010002 — Attempt to write a read-only object", the error, or nothing. */
export function resultDetail(entry: AuditEntry): string {
  const meaning = entry.message ?? entry.error;
  if (entry.abort_code) {
    const code = formatAbortCode(entry.abort_code);
    return meaning ? `${code} — ${meaning}` : code;
  }
  return meaning ?? "";
}

/** The undo dialog's question: what gets written where. */
export function undoText(entry: AuditEntry): string {
  const object = objectText(entry);
  const values = { old: valueText(entry.old), new: valueText(entry.new) };
  if (object && entry.node !== null) {
    return i18n.t("logs.audit.undo.toNode", { ...values, object, node: entry.node });
  }
  if (object) return i18n.t("logs.audit.undo.toObject", { ...values, object });
  return i18n.t("logs.audit.undo.previous", { ...values, what: entry.what });
}
