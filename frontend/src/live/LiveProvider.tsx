import { useEffect, useState, type ReactNode } from "react";

import { useSessionControl } from "../session/context";

import { clientName, CLIENT_ID } from "../api/clientId";
import { LiveConnection, liveUrl } from "./connection";
import { LiveStoreContext } from "./context";
import { refreshNodes } from "./nodes";
import { LiveStore } from "./store";

interface Props {
  children: ReactNode;
  /** Tests pass a prepared store and no connection. */
  store?: LiveStore;
  connect?: boolean;
}

export function LiveProvider({ children, store: given, connect = true }: Props): ReactNode {
  const [store] = useState(() => given ?? new LiveStore());
  const recheck = useSessionControl()?.recheck;

  useEffect(() => {
    if (!connect) return undefined;
    const connection = new LiveConnection(store, {
      url: liveUrl(window.location),
      hello: { type: "hello", client_id: CLIENT_ID, name: clientName() },
      onRefused: () => recheck?.(),
    });
    store.setSender((message) => connection.send(message));
    connection.start();
    // A hidden page cannot hold a jog button: the server stops this tab's jogs at once.
    const visibility = (): void => {
      if (document.visibilityState === "hidden") store.send({ type: "page_hidden" });
    };
    document.addEventListener("visibilitychange", visibility);
    return () => {
      document.removeEventListener("visibilitychange", visibility);
      store.setSender(null);
      connection.stop();
    };
  }, [store, connect, recheck]);

  useEffect(() => {
    if (!connect) return undefined;
    void refreshNodes(store);
    // A node that appears, disappears or moves (node-id change, scan) changes the id set the
    // WebSocket reports: fetch the details then, not on every 5 Hz update.
    let ids = store.getSnapshot().liveIds;
    return store.subscribe(() => {
      const next = store.getSnapshot().liveIds;
      if (next === ids) return;
      ids = next;
      void refreshNodes(store);
    });
  }, [store, connect]);

  return <LiveStoreContext value={store}>{children}</LiveStoreContext>;
}
