// Load data for a page and reload on demand, with errors kept as ApiError for display.
// Requests of a previous key are aborted, so a fast node switch never shows stale data.
import { useCallback, useEffect, useRef, useState } from "react";

import { asApiError, type ApiError } from "../api/errors";

interface Loaded<T> {
  key: string;
  data?: T;
  error?: ApiError;
}

export interface ApiState<T> {
  data: T | undefined;
  error: ApiError | null;
  loading: boolean;
  reload: () => void;
  /** Replace the data locally (e.g. with a write's answer) without another request. */
  setData: (update: (old: T | undefined) => T | undefined) => void;
}

export function useApi<T>(load: (signal: AbortSignal) => Promise<T>, key: string): ApiState<T> {
  const loadRef = useRef(load);
  useEffect(() => {
    loadRef.current = load;
  });
  const [nonce, setNonce] = useState(0);
  const [state, setState] = useState<Loaded<T> | null>(null);
  const fullKey = `${key}#${nonce}`;

  useEffect(() => {
    const controller = new AbortController();
    loadRef.current(controller.signal).then(
      (data) => {
        if (!controller.signal.aborted) setState({ key: fullKey, data });
      },
      (error: unknown) => {
        if (!controller.signal.aborted) setState({ key: fullKey, error: asApiError(error) });
      },
    );
    return () => controller.abort();
  }, [fullKey]);

  const reload = useCallback(() => setNonce((n) => n + 1), []);
  const setData = useCallback((update: (old: T | undefined) => T | undefined) => {
    setState((old) => (old ? { ...old, data: update(old.data) } : old));
  }, []);

  // Data of a previous key is kept for display while the next load runs (no flicker), but
  // only for a reload of the same key: another node's data must not show under this one.
  const sameResource = state?.key.startsWith(`${key}#`) ?? false;
  return {
    data: sameResource ? state?.data : undefined,
    error: state?.key === fullKey ? (state.error ?? null) : null,
    loading: state?.key !== fullKey,
    reload,
    setData,
  };
}

/** Run one action (a button's request) with its own busy flag and error. */
export function useAction<A extends unknown[], R>(
  action: (...args: A) => Promise<R>,
): {
  run: (...args: A) => Promise<R | undefined>;
  busy: boolean;
  error: ApiError | null;
  clearError: () => void;
} {
  const [busy, setBusy] = useState(false);
  const [error, setError] = useState<ApiError | null>(null);
  const actionRef = useRef(action);
  useEffect(() => {
    actionRef.current = action;
  });
  const run = useCallback(async (...args: A): Promise<R | undefined> => {
    setBusy(true);
    setError(null);
    try {
      return await actionRef.current(...args);
    } catch (caught) {
      setError(asApiError(caught));
      return undefined;
    } finally {
      setBusy(false);
    }
  }, []);
  const clearError = useCallback(() => setError(null), []);
  return { run, busy, error, clearError };
}
