// The live check's capture: started on demand, polled ~3 Hz while the page is visible, stopped
// when the page goes away (a capture left running costs the server nothing but is untidy).
import { useCallback, useEffect, useRef, useState } from "react";

import { asApiError, type ApiError } from "../../api/errors";
import { readLive, startLive, stopLive } from "./pdoApi";
import type { LiveCapture } from "./types";

export const POLL_MS = 330;

function useVisible(): boolean {
  const [visible, setVisible] = useState(() => document.visibilityState !== "hidden");
  useEffect(() => {
    const update = (): void => setVisible(document.visibilityState !== "hidden");
    document.addEventListener("visibilitychange", update);
    return () => document.removeEventListener("visibilitychange", update);
  }, []);
  return visible;
}

export interface LiveState {
  capture: LiveCapture | null;
  running: boolean;
  error: ApiError | null;
  start: () => Promise<void>;
  stop: () => Promise<void>;
}

export function useLiveCapture(node: number): LiveState {
  const [capture, setCapture] = useState<LiveCapture | null>(null);
  const [running, setRunning] = useState(false);
  const [error, setError] = useState<ApiError | null>(null);
  const visible = useVisible();
  const runningRef = useRef(false);

  const start = useCallback(async () => {
    setError(null);
    try {
      setCapture(await startLive(node));
      runningRef.current = true;
      setRunning(true);
    } catch (caught) {
      setError(asApiError(caught));
    }
  }, [node]);

  const stop = useCallback(async () => {
    runningRef.current = false;
    setRunning(false);
    try {
      await stopLive(node);
    } catch (caught) {
      setError(asApiError(caught));
    }
  }, [node]);

  useEffect(() => {
    if (!running || !visible) return undefined;
    const controller = new AbortController();
    let timer: ReturnType<typeof setTimeout> | undefined;
    const poll = async (): Promise<void> => {
      try {
        const next = await readLive(node, controller.signal);
        if (controller.signal.aborted) return;
        setCapture(next);
        setError(null);
      } catch (caught) {
        if (controller.signal.aborted) return;
        setError(asApiError(caught));
      }
      timer = setTimeout(() => void poll(), POLL_MS);
    };
    void poll();
    return () => {
      controller.abort();
      clearTimeout(timer);
    };
  }, [node, running, visible]);

  // Leaving the page stops the capture.
  useEffect(
    () => () => {
      if (runningRef.current) void stopLive(node).catch(() => undefined);
    },
    [node],
  );

  return { capture, running, error, start, stop };
}
