// A fetch stand-in for page tests: routes "METHOD /path" to canned answers and records calls.
import { vi } from "vitest";

/** May answer asynchronously (e.g. after reading the request's body). */
export type Handler = (request: Request) => unknown;

export interface FetchStub {
  calls: { method: string; path: string; body: string }[];
  /** Full request URLs, query strings included. */
  urls: string[];
}

export function json(body: unknown, status = 200): Response {
  return new Response(JSON.stringify(body), {
    status,
    headers: { "Content-Type": "application/json" },
  });
}

/** Install a fetch that answers from `routes`; a value that is not a Response is sent as JSON. */
export function stubFetch(routes: Record<string, Handler | object>): FetchStub {
  const stub: FetchStub = { calls: [], urls: [] };
  vi.stubGlobal("fetch", async (input: Request) => {
    const url = new URL(input.url);
    const key = `${input.method} ${url.pathname}`;
    const body = input.method === "GET" ? "" : await input.clone().text();
    stub.calls.push({ method: input.method, path: url.pathname, body });
    stub.urls.push(input.url);
    const route = routes[key];
    if (route === undefined) return json({ error: "error", message: `no stub for ${key}` }, 500);
    const answer: unknown = typeof route === "function" ? await (route as Handler)(input) : route;
    return answer instanceof Response ? answer : json(answer);
  });
  return stub;
}
