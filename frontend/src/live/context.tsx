// React access to the live store: a provider owns one store and (in the app) one connection;
// hooks read slices with useSyncExternalStore so only subscribers of a slice re-render.
import { createContext, useContext, useSyncExternalStore } from "react";

import type { LiveSnapshot, LiveStore } from "./store";

export const LiveStoreContext = createContext<LiveStore | null>(null);

export function useLiveStore(): LiveStore {
  const store = useContext(LiveStoreContext);
  if (!store) throw new Error("useLiveStore needs a <LiveProvider> above it");
  return store;
}

/**
 * Read one slice of the live snapshot. The selector must return a value that stays identical
 * while its data is unchanged (a field of the snapshot, a primitive), or React re-renders on
 * every store update.
 */
export function useLive<T>(selector: (snapshot: LiveSnapshot) => T): T {
  const store = useLiveStore();
  return useSyncExternalStore(store.subscribe, () => selector(store.getSnapshot()));
}
