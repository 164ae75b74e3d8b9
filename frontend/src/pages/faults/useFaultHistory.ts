// The Faults tab's data: the node's active fault from the live store (the banner's source), and
// its fault history by REST, read once on open and again only when the live channel says it
// changed: never on a timer.
import { useCallback, useEffect, useRef, useState } from "react";

import { FAULT_HISTORY_PAGE, nodeFaults } from "../../api/faultsApi";
import { useApi, type ApiState } from "../../lib/useApi";
import { useLive, useLiveStore } from "../../live/context";
import type { Fault, NodeFaults } from "./types";

/** A `fault` message (or a reconnect) reads the history this long after it: the messages of
 * one EMCY (the fault, then the state read after it, when it is stored) and a storm's many
 * cost one read per window, not one each. */
export const HISTORY_REFETCH_MS = 400;
/** The most entries "Older…" asks for (the route's limit). */
export const HISTORY_MAX = 10_000;

export interface FaultHistory extends ApiState<NodeFaults> {
  allBuses: boolean;
  setAllBuses: (all: boolean) => void;
  /** Whether the list may have older entries to load (fewer shown than stored). */
  hasOlder: boolean;
  /** Load the next page of older entries. */
  older: () => void;
}

/**
 * GET /api/nodes/{node}/faults on open, then once (HISTORY_REFETCH_MS after the first) for each
 * burst of the channel's `fault` messages for the node: the server sends one when its active
 * fault changes and when its EMCYs are stored. Also after a reconnect (what the channel missed
 * while down), on "Other buses too" and for older pages. Each answer's `active` goes to the live
 * store unless a `fault` message came since it was asked (the store keeps the newest).
 */
export function useFaultHistory(node: number): FaultHistory {
  const store = useLiveStore();
  const [allBuses, setAllBusesState] = useState(false);
  const [limit, setLimit] = useState(FAULT_HISTORY_PAGE);
  // keyed by node only: a re-read keeps the list shown until its answer (no flicker)
  const faults = useApi(async (signal) => {
    const version = store.faultVersion();
    const answer = await nodeFaults(node, signal, { allBuses, limit });
    if (!signal.aborted) store.setNodeFault(node, answer.active, version);
    return answer;
  }, `faults-${node}`);
  const { reload } = faults;

  const timer = useRef<ReturnType<typeof setTimeout> | null>(null);
  const schedule = useCallback(() => {
    if (timer.current !== null) return; // the read already planned covers this one
    timer.current = setTimeout(() => {
      timer.current = null;
      reload();
    }, HISTORY_REFETCH_MS);
  }, [reload]);
  useEffect(
    () => () => {
      if (timer.current !== null) clearTimeout(timer.current);
      timer.current = null;
    },
    [],
  );

  useEffect(
    () =>
      store.subscribeFaults((changed) => {
        if (changed === node) schedule();
      }),
    [store, node, schedule],
  );

  // a (re)connected channel may have missed messages while it was down: read once
  const open = useLive((s) => s.link.state === "open");
  const wasOpen = useRef(open);
  useEffect(() => {
    if (open && !wasOpen.current) schedule();
    wasOpen.current = open;
  }, [open, schedule]);

  const setAllBuses = useCallback(
    (all: boolean) => {
      setAllBusesState(all);
      reload();
    },
    [reload],
  );
  const older = useCallback(() => {
    setLimit((current) => Math.min(current + FAULT_HISTORY_PAGE, HISTORY_MAX));
    reload();
  }, [reload]);
  const data = faults.data;
  const hasOlder = data !== undefined && data.history.length < data.total && limit < HISTORY_MAX;
  return { ...faults, allBuses, setAllBuses, hasOlder, older };
}

/** The node's active fault as the live store has it (the fault banner's source): undefined
 * until known, from a `fault` message or `known` (a GET of the node's faults answered). */
export function useActiveFault(node: number, known: boolean): Fault | null | undefined {
  const live = useLive((s) => s.faults[node]);
  return live ?? (known ? null : undefined);
}
