// A canned commissioning server for the Commission tab's tests (English and zh-CN): one record
// whose steps change as the page runs, signs and skips them.
import { stubFetch, type FetchStub } from "../../test/fetchStub";
import type { CommissioningRecord, CommissioningStep } from "./types";

/** A server holding one record whose steps change as the page runs and signs them. */
export function serve(
  initial: CommissioningRecord,
  runs: Record<string, () => unknown> = {},
  extra: Record<string, (request: Request) => unknown> = {},
): FetchStub {
  let current = initial;
  const replace = (answer: CommissioningStep): CommissioningStep => {
    current = {
      ...current,
      steps: current.steps.map((s) => (s.key === answer.key ? answer : s)),
    };
    return answer;
  };
  const routes: Record<string, (request: Request) => unknown> = {
    ...extra,
    "GET /api/commissioning": () => [current],
    [`GET /api/commissioning/${initial.id}`]: () => current,
  };
  for (const [key, answer] of Object.entries(runs)) {
    routes[`POST /api/commissioning/${initial.id}/steps/${key}/run`] = async () => {
      const value = await answer();
      return value instanceof Response ? value : replace(value as CommissioningStep);
    };
  }
  for (const s of initial.steps) {
    routes[`PUT /api/commissioning/${initial.id}/steps/${s.key}`] = async (request) => {
      const body = (await request.json()) as { status: "done" | "skipped"; reason?: string };
      return replace({
        ...s,
        status: body.status,
        reason: body.reason ?? null,
        by: "local",
        at: 1_764_000_000,
      });
    };
  }
  return stubFetch(routes);
}
