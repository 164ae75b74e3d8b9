// The audit log's entries as GET /api/audit returns them.
import type { components } from "../../api/schema";

export type AuditEntry = components["schemas"]["AuditEntry"];

export type AuditResult = AuditEntry["result"];

/** The filters as the form holds them (text, as typed). */
export interface AuditFilters {
  node: string;
  /** A datetime-local value, "2025-05-01T14:30", in the browser's time zone. */
  since: string;
  user: string;
  action: string;
}
