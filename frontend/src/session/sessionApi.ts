import { api, call } from "../api/client";
import { asApiError, toApiError } from "../api/errors";
import type { SessionInfo } from "./types";

/** Who this browser is logged in as; a 401 (ApiError) when a login is needed. */
export function fetchSession(): Promise<SessionInfo> {
  return call(api.GET("/api/session"));
}

/** Exchange the token for the server's HttpOnly session cookie. */
export function logIn(token: string): Promise<SessionInfo> {
  return call(api.POST("/api/login", { body: { token } }));
}

/** The server clears the cookie and answers 204 (no body, so not through `call`). */
export async function logOut(): Promise<void> {
  let response: Response;
  let error: unknown;
  try {
    ({ response, error } = await api.POST("/api/logout"));
  } catch (caught) {
    throw asApiError(caught);
  }
  if (!response.ok) throw toApiError(response.status, error, response.statusText);
}
