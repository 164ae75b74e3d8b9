// One error type for every failed API call, built from the backend's single error shape
// (docs/api.md, "Errors"): {error: kind, message, abort_code?, ...}.
import { i18n } from "../i18n";
import { abortMeaning, serverText, type ServerText, type TextParams } from "../lib/serverText";

export type ApiErrorKind =
  | "sdo_abort"
  | "node_stopped"
  | "timeout"
  | "sdo_protocol"
  | "interrupted"
  | "node_not_found"
  | "bus_not_connected"
  | "invalid_value"
  | "invalid_request"
  | "confirmation_required"
  | "identity_mismatch"
  | "validation_error"
  | "unauthorized"
  | "forbidden"
  | "rate_limited"
  | "not_undoable"
  | "already_undone"
  | "changed_since"
  | "network"
  | "error";

const KNOWN_KINDS: ReadonlySet<string> = new Set<ApiErrorKind>([
  "sdo_abort",
  "node_stopped",
  "timeout",
  "sdo_protocol",
  "interrupted",
  "node_not_found",
  "bus_not_connected",
  "invalid_value",
  "invalid_request",
  "confirmation_required",
  "identity_mismatch",
  "validation_error",
  "unauthorized",
  "forbidden",
  "rate_limited",
  "not_undoable",
  "already_undone",
  "changed_since",
  "network",
  "error",
]);

export class ApiError extends Error {
  readonly status: number;
  readonly kind: ApiErrorKind;
  readonly abortCode: string | null;
  /** The node the error concerns, when the server names one. */
  readonly node: number | null;
  /** Seconds to wait before trying again (a rate-limited login). */
  readonly retryAfterS: number | null;
  /** The message by id, for the page's language (lib/serverText.ts). */
  readonly said: Pick<ServerText, "message_id" | "params"> | null;

  constructor(
    status: number,
    kind: ApiErrorKind,
    message: string,
    abortCode: string | null,
    node: number | null = null,
    retryAfterS: number | null = null,
    said: Pick<ServerText, "message_id" | "params"> | null = null,
  ) {
    super(message);
    this.name = "ApiError";
    this.status = status;
    this.kind = kind;
    this.abortCode = abortCode;
    this.node = node;
    this.retryAfterS = retryAfterS;
    this.said = said;
  }

  /** The message in the page's language (the server's English without an id it knows). */
  text(): string {
    if (this.abortCode) return abortMeaning(this.abortCode, this.message);
    return serverText({ message: this.message, ...this.said });
  }

  /** What the user reads: an SDO abort shows its raw code beside the meaning. */
  describe(): string {
    if (this.abortCode) return `${formatAbortCode(this.abortCode)} — ${this.text()}`;
    return this.text();
  }
}

/** "0x6010002", "06010002" or a number → "0x06010002" (the form the manuals print). */
export function formatAbortCode(code: string | number): string {
  const value = typeof code === "number" ? code : Number.parseInt(code.replace(/^0x/i, ""), 16);
  if (!Number.isFinite(value)) return String(code);
  return `0x${value.toString(16).toUpperCase().padStart(8, "0")}`;
}

function isRecord(value: unknown): value is Record<string, unknown> {
  return typeof value === "object" && value !== null && !Array.isArray(value);
}

/** FastAPI's own 422 body: {detail: [{loc: [...], msg}]} → "body.value: field required". */
function describeValidation(detail: unknown): string {
  if (!Array.isArray(detail)) return typeof detail === "string" ? detail : "Invalid request";
  const parts = detail.map((item: unknown) => {
    if (!isRecord(item)) return String(item);
    const loc = Array.isArray(item.loc) ? item.loc.map(String).join(".") : "";
    const msg = typeof item.msg === "string" ? item.msg : "invalid";
    return loc ? `${loc}: ${msg}` : msg;
  });
  return parts.join("; ") || "Invalid request";
}

// A 401 on any request means there is no (longer a) login session. Every failed request of
// every page passes through toApiError, so this is the one place that notices it; the session
// context listens and shows the login screen over whatever page asked.
const unauthorizedListeners = new Set<() => void>();

/** Call `listener` on every 401 answer; returns the unsubscribe function. */
export function onUnauthorized(listener: () => void): () => void {
  unauthorizedListeners.add(listener);
  return () => {
    unauthorizedListeners.delete(listener);
  };
}

/** Turn whatever came back with a non-2xx status into an ApiError. */
export function toApiError(status: number, body: unknown, statusText = ""): ApiError {
  if (status === 401) for (const listener of [...unauthorizedListeners]) listener();
  if (isRecord(body)) {
    if (typeof body.error === "string") {
      const kind = KNOWN_KINDS.has(body.error) ? (body.error as ApiErrorKind) : "error";
      const message = typeof body.message === "string" ? body.message : body.error;
      const abort = typeof body.abort_code === "string" ? body.abort_code : null;
      const node = typeof body.node === "number" ? body.node : null;
      const retry = typeof body.retry_after_s === "number" ? body.retry_after_s : null;
      const said =
        typeof body.message_id === "string" && isRecord(body.params)
          ? { message_id: body.message_id, params: body.params as TextParams }
          : null;
      return new ApiError(status, kind, message, abort, node, retry, said);
    }
    if ("detail" in body) {
      return new ApiError(status, "validation_error", describeValidation(body.detail), null);
    }
  }
  if (typeof body === "string" && body.trim()) {
    return new ApiError(status, "error", body.trim(), null);
  }
  return new ApiError(status, "error", `HTTP ${status}${statusText ? ` ${statusText}` : ""}`, null);
}

/** Any thrown value → ApiError, so components render one kind of error. */
export function asApiError(error: unknown): ApiError {
  if (error instanceof ApiError) return error;
  if (error instanceof DOMException && error.name === "AbortError") {
    return new ApiError(0, "network", i18n.t("errors.cancelled"), null);
  }
  if (error instanceof Error) {
    // fetch rejects with a TypeError when the server is unreachable.
    return new ApiError(
      0,
      "network",
      i18n.t("errors.unreachable", { reason: error.message }),
      null,
    );
  }
  return new ApiError(0, "error", String(error), null);
}
