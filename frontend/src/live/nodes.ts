// The node list (GET /api/nodes) kept in the live store, so the sidebar, the Network table and
// the node pages agree on which nodes exist and what they are called.
import { api, call } from "../api/client";
import { asApiError } from "../api/errors";
import type { LiveStore } from "./store";

export async function refreshNodes(store: LiveStore): Promise<void> {
  try {
    store.setInfos(await call(api.GET("/api/nodes")));
  } catch (error) {
    store.setInfosError(asApiError(error).describe());
  }
}
