import { api, call } from "../../api/client";
import type { AuditEntry, AuditFilters } from "./types";

export const PAGE_SIZE = 100;

export interface AuditQuery {
  node?: number;
  since?: number;
  user?: string;
  action?: string;
}

/** The form's text → the route's query; blanks and nonsense are left out, not sent. */
export function auditQuery(filters: AuditFilters): AuditQuery {
  const query: AuditQuery = {};
  const node = filters.node.trim();
  if (/^\d{1,3}$/.test(node)) query.node = Number(node);
  if (filters.since) {
    // datetime-local has no zone: the Date constructor reads it as the browser's local time
    const ms = new Date(filters.since).getTime();
    if (Number.isFinite(ms)) query.since = Math.floor(ms / 1000);
  }
  if (filters.user.trim()) query.user = filters.user.trim();
  if (filters.action.trim()) query.action = filters.action.trim();
  return query;
}

/** "/api/audit/export?format=csv&node=1&…": a plain link, so the browser downloads it. */
export function exportUrl(query: AuditQuery): string {
  const params = new URLSearchParams({ format: "csv" });
  for (const [name, value] of Object.entries(query)) {
    if (value !== undefined) params.set(name, String(value));
  }
  return `/api/audit/export?${params.toString()}`;
}

/** One page, newest first; `before` (an entry id) pages to older ones. */
export function fetchAudit(
  query: AuditQuery,
  before: number | null,
  signal?: AbortSignal,
): Promise<AuditEntry[]> {
  return call(
    api.GET("/api/audit", {
      params: { query: { ...query, limit: PAGE_SIZE, ...(before === null ? {} : { before }) } },
      signal,
    }),
  );
}

/** Writes the entry's old value back; the answer is the undo's own entry. Without `force` the
 * server refuses (409 changed_since) when the value is no longer the one the entry left. */
export function undoEntry(id: number, force = false): Promise<AuditEntry> {
  return call(
    api.POST("/api/audit/{entry_id}/undo", {
      params: { path: { entry_id: id } },
      body: { force },
    }),
  );
}
