// One error type for every failed API call, built from the backend's single error shape
// (docs/api.md, "Errors"): {error: kind, message, abort_code?, ...}.

export type ApiErrorKind =
  | "sdo_abort"
  | "node_stopped"
  | "timeout"
  | "interrupted"
  | "node_not_found"
  | "bus_not_connected"
  | "invalid_value"
  | "invalid_request"
  | "confirmation_required"
  | "identity_mismatch"
  | "validation_error"
  | "network"
  | "error";

const KNOWN_KINDS: ReadonlySet<string> = new Set<ApiErrorKind>([
  "sdo_abort",
  "node_stopped",
  "timeout",
  "interrupted",
  "node_not_found",
  "bus_not_connected",
  "invalid_value",
  "invalid_request",
  "confirmation_required",
  "identity_mismatch",
  "validation_error",
  "network",
  "error",
]);

export class ApiError extends Error {
  readonly status: number;
  readonly kind: ApiErrorKind;
  readonly abortCode: string | null;
  /** The node the error concerns, when the server names one. */
  readonly node: number | null;

  constructor(
    status: number,
    kind: ApiErrorKind,
    message: string,
    abortCode: string | null,
    node: number | null = null,
  ) {
    super(message);
    this.name = "ApiError";
    this.status = status;
    this.kind = kind;
    this.abortCode = abortCode;
    this.node = node;
  }

  /** What the user reads: an SDO abort shows its raw code beside the meaning. */
  describe(): string {
    if (this.abortCode) return `${formatAbortCode(this.abortCode)} — ${this.message}`;
    return this.message;
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

/** Turn whatever came back with a non-2xx status into an ApiError. */
export function toApiError(status: number, body: unknown, statusText = ""): ApiError {
  if (isRecord(body)) {
    if (typeof body.error === "string") {
      const kind = KNOWN_KINDS.has(body.error) ? (body.error as ApiErrorKind) : "error";
      const message = typeof body.message === "string" ? body.message : body.error;
      const abort = typeof body.abort_code === "string" ? body.abort_code : null;
      const node = typeof body.node === "number" ? body.node : null;
      return new ApiError(status, kind, message, abort, node);
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
    return new ApiError(0, "network", "Request cancelled", null);
  }
  if (error instanceof Error) {
    // fetch rejects with a TypeError when the server is unreachable.
    return new ApiError(0, "network", `Server unreachable: ${error.message}`, null);
  }
  return new ApiError(0, "error", String(error), null);
}
