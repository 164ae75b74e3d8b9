// React access to the login session. Without a provider (page tests) everyone is the local
// engineer, as on a server without tokens.
import { createContext, useContext, useMemo } from "react";

import { LOCAL_SESSION, permit, type Permit } from "./permit";
import type { Permission, SessionInfo } from "./types";

export interface SessionControl {
  info: SessionInfo;
  logout: () => Promise<void>;
  /** Ask the server again who we are (after the live socket was refused, say). */
  recheck: () => void;
}

export const SessionContext = createContext<SessionControl | null>(null);

export function useSession(): SessionInfo {
  return useContext(SessionContext)?.info ?? LOCAL_SESSION;
}

export function useSessionControl(): SessionControl | null {
  return useContext(SessionContext);
}

/** May this login `operate` (run the drives) or `configure` (change their setup)? */
export function useMay(need: Permission): Permit {
  const session = useSession();
  return useMemo(() => permit(session, need), [session, need]);
}
