// The typed API client. Types come from schema.d.ts, which is generated from the backend's
// OpenAPI schema (`npm run gen:api`) and never edited: a changed route or field breaks the
// type check instead of a page at run time.
import createClient from "openapi-fetch";

import { ApiError, asApiError, toApiError } from "./errors";
import type { paths } from "./schema";

// Same-origin requests: the backend serves this app, and Vite proxies /api in development.
// The origin (rather than "") keeps URLs absolute, which the fetch of Node-based unit tests
// needs; in the browser both mean the same thing.
const origin = typeof window === "undefined" ? "" : window.location.origin;

export const api = createClient<paths>({
  baseUrl: origin,
  // Looked up per call so tests can stub the global fetch after this module is loaded.
  fetch: (request: Request) => globalThis.fetch(request),
});

interface CallResult<T> {
  data?: T;
  error?: unknown;
  response: Response;
}

/**
 * Await an api.GET/POST/... call and return its data, or throw an ApiError built from the
 * backend's `{error, message, abort_code}` body. Every page goes through this one helper;
 * `toError` builds the error (the motion routes pass theirs, which knows their refusals).
 */
export async function call<T>(
  request: Promise<CallResult<T>>,
  toError: (status: number, body: unknown, statusText?: string) => ApiError = toApiError,
): Promise<T> {
  let result: CallResult<T>;
  try {
    result = await request;
  } catch (error) {
    throw asApiError(error);
  }
  const { response } = result;
  if (!response.ok) throw toError(response.status, result.error, response.statusText);
  if (result.data === undefined) {
    throw new ApiError(response.status, "error", "The server sent an empty answer", null);
  }
  return result.data;
}

/** Multipart body with one `file` field (and form fields such as `confirm`), for the EDS/DCF
 * upload routes. */
export function fileForm(file: File | null, fields: Record<string, string> = {}): FormData {
  const form = new FormData();
  if (file) form.append("file", file, file.name);
  for (const [name, value] of Object.entries(fields)) form.append(name, value);
  return form;
}

/**
 * The generated types describe an uploaded file as `string` (OpenAPI `format: binary`), while
 * the browser sends a File inside FormData. This is the one place that bridges the two: the
 * body value is ignored because the serializer builds the form from the File itself.
 */
export function uploadBody(
  file: File | null,
  fields: Record<string, string> = {},
): {
  body: { file: string };
  bodySerializer: () => FormData;
} {
  return { body: { file: file?.name ?? "" }, bodySerializer: () => fileForm(file, fields) };
}

/** Object-dictionary address as the routes want it: hex without prefix ("6041", "0A"). */
export function odPath(index: number, subindex: number): { index: string; subindex: string } {
  return {
    index: index.toString(16).toUpperCase().padStart(4, "0"),
    subindex: subindex.toString(16).toUpperCase().padStart(2, "0"),
  };
}
