// Check a capture request as the form changes: debounced, the previous answer kept (marked as
// checking) until the next arrives, an older answer never shown for a newer request.
import { useEffect, useState } from "react";

import { asApiError, type ApiError } from "../../api/errors";
import { planCapture } from "./scopeApi";
import type { CaptureRequest, ScopePlan } from "./types";

interface Answer {
  key: string;
  plan: ScopePlan | null;
  error: ApiError | null;
}

export interface PlanState {
  /** The latest plan (of this request, or the previous one while `checking`). */
  plan: ScopePlan | null;
  error: ApiError | null;
  checking: boolean;
  /** The plan answers the request as it is now. */
  current: boolean;
}

/** `refresh` re-checks the same request (the bus changed: a capture ended). While `paused`
 * (a capture is recording: the scope's own TPDOs are in use) the last answer stays. */
export function usePlan(
  request: CaptureRequest | null,
  {
    refresh = 0,
    paused = false,
    delayMs = 400,
  }: { refresh?: number; paused?: boolean; delayMs?: number } = {},
): PlanState {
  const key = request ? `${refresh}|${JSON.stringify(request)}` : "";
  const [answer, setAnswer] = useState<Answer | null>(null);

  useEffect(() => {
    if (!key || paused) return;
    const controller = new AbortController();
    const body = JSON.parse(key.slice(key.indexOf("|") + 1)) as CaptureRequest;
    const timer = setTimeout(() => {
      planCapture(body, controller.signal).then(
        (plan) => {
          if (!controller.signal.aborted) setAnswer({ key, plan, error: null });
        },
        (error: unknown) => {
          if (!controller.signal.aborted) setAnswer({ key, plan: null, error: asApiError(error) });
        },
      );
    }, delayMs);
    return () => {
      clearTimeout(timer);
      controller.abort();
    };
  }, [key, paused, delayMs]);

  if (!key) return { plan: null, error: null, checking: false, current: false };
  if (paused) {
    return {
      plan: answer?.plan ?? null,
      error: answer?.error ?? null,
      checking: false,
      current: true,
    };
  }
  const current = answer?.key === key;
  return {
    plan: answer?.plan ?? null,
    error: current ? answer.error : null,
    checking: !current,
    current,
  };
}
