// The drive's live state for the Drive tab: pushed on the WebSocket after a `watch_drive`
// where the server offers that, polled at ~5 Hz (only while the page is visible) whenever no
// push has arrived for a second. An action's answer replaces the state at once, and a poll sent
// before it was answered does not undo it.
import { useCallback, useEffect, useRef, useState } from "react";

import { getController, getDrive } from "../../api/driveApi";
import { asApiError, type ApiError } from "../../api/errors";
import { useLive, useLiveStore } from "../../live/context";
import type { ControllerInfo, DriveState } from "./types";

export const POLL_MS = 200;
/** A pushed state younger than this makes polling unnecessary. */
export const PUSH_FRESH_MS = 1000;

interface Stamped<T> {
  value: T;
  at: number;
}

function newer<T>(a: Stamped<T> | null, b: Stamped<T> | null): T | undefined {
  if (!a) return b?.value;
  if (!b) return a.value;
  return a.at >= b.at ? a.value : b.value;
}

/** A polled answer is as old as its request: an action answered meanwhile stays on screen. */
function polled<T>(value: T, sent: number) {
  return (current: Stamped<T> | null): Stamped<T> =>
    current && current.at >= sent ? current : { value, at: sent };
}

function pageVisible(): boolean {
  return typeof document === "undefined" || document.visibilityState !== "hidden";
}

export function useDrive(node: number): {
  drive: DriveState | undefined;
  error: ApiError | null;
  /** Put an action's answer on screen. */
  show: (state: DriveState) => void;
} {
  const store = useLiveStore();
  const pushed = useLive((s) => s.drives[node]);
  const pushedAt = useLive((s) => s.drivesAt[node]);
  const linkOpen = useLive((s) => s.link.state === "open");
  const [local, setLocal] = useState<Stamped<DriveState> | null>(null);
  const [error, setError] = useState<ApiError | null>(null);
  const inFlight = useRef(false);

  const show = useCallback((state: DriveState) => setLocal({ value: state, at: Date.now() }), []);

  useEffect(() => {
    if (linkOpen) store.send({ type: "watch_drive", node });
  }, [store, node, linkOpen]);

  useEffect(() => {
    const controller = new AbortController();
    const poll = (force: boolean): void => {
      if (inFlight.current || (!force && !pageVisible())) return;
      const at = store.getSnapshot().drivesAt[node] ?? 0;
      if (!force && Date.now() - at < PUSH_FRESH_MS) return;
      inFlight.current = true;
      const sent = Date.now();
      getDrive(node, controller.signal).then(
        (state) => {
          inFlight.current = false;
          if (controller.signal.aborted) return;
          setLocal(polled(state, sent));
          setError(null);
        },
        (caught: unknown) => {
          inFlight.current = false;
          if (!controller.signal.aborted) setError(asApiError(caught));
        },
      );
    };
    poll(true);
    const timer = setInterval(() => poll(false), POLL_MS);
    return () => {
      clearInterval(timer);
      controller.abort();
      inFlight.current = false;
    };
  }, [store, node]);

  const drive = newer(local, pushed && pushedAt ? { value: pushed, at: pushedAt } : null);
  return { drive, error, show };
}

export const CONTROLLER_POLL_MS = 2000;

/** Who holds the node's motion control: fetched, refreshed every 2 s, replaced by pushes
 * (a push may leave out the heartbeat protection: the fetched one stays). */
export function useController(node: number): {
  controller: ControllerInfo | undefined;
  error: ApiError | null;
  show: (info: ControllerInfo) => void;
} {
  const pushed = useLive((s) => s.controllers[node]);
  const pushedAt = useLive((s) => s.controllersAt[node]);
  const [local, setLocal] = useState<Stamped<ControllerInfo> | null>(null);
  const [error, setError] = useState<ApiError | null>(null);
  const show = useCallback((info: ControllerInfo) => setLocal({ value: info, at: Date.now() }), []);

  useEffect(() => {
    const controller = new AbortController();
    const load = (force: boolean): void => {
      if (!force && !pageVisible()) return;
      const sent = Date.now();
      getController(node, controller.signal).then(
        (info) => {
          if (controller.signal.aborted) return;
          setLocal(polled(info, sent));
          setError(null);
        },
        (caught: unknown) => {
          if (!controller.signal.aborted) setError(asApiError(caught));
        },
      );
    };
    load(true);
    const timer = setInterval(() => load(false), CONTROLLER_POLL_MS);
    return () => {
      clearInterval(timer);
      controller.abort();
    };
  }, [node]);

  const latest = newer(local, pushed && pushedAt ? { value: pushed, at: pushedAt } : null);
  const controller =
    latest && local && latest !== local.value ? { ...local.value, ...latest } : latest;
  return { controller, error, show };
}
