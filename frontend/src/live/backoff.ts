// Reconnect delays for the live channel: fast first retries (a restarted server is back within
// a second), then exponential up to a ceiling so a stopped server is not hammered.

export interface BackoffOptions {
  initialMs: number;
  maxMs: number;
  /** Fraction of random spread added on top, so many tabs do not reconnect in lockstep. */
  jitter: number;
}

export const DEFAULT_BACKOFF: BackoffOptions = { initialMs: 500, maxMs: 10_000, jitter: 0.2 };

/** Delay before reconnect attempt number `attempt` (0 for the first retry). */
export function backoffDelay(
  attempt: number,
  options: BackoffOptions = DEFAULT_BACKOFF,
  random: () => number = Math.random,
): number {
  const base = Math.min(options.maxMs, options.initialMs * 2 ** Math.max(0, attempt));
  return Math.round(base * (1 + options.jitter * random()));
}
