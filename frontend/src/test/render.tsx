// Render a page inside the providers the app gives it: a router at `url`, a live store with
// no WebSocket (tests fill the store themselves) and, when given, a login session (without one
// pages see the local engineer of a server without tokens).
import { render, type RenderResult } from "@testing-library/react";
import type { ReactNode } from "react";
import { MemoryRouter } from "react-router";

import { LiveProvider } from "../live/LiveProvider";
import { LiveStore } from "../live/store";
import { SessionContext } from "../session/context";
import type { Role, SessionInfo } from "../session/types";

/** A logged-in session of `role` on a server with tokens. */
export function sessionAs(role: Role, user: string = role): SessionInfo {
  return {
    user,
    role,
    auth_required: true,
    may: { operate: role !== "viewer", configure: role === "engineer" },
  };
}

export function renderPage(
  ui: ReactNode,
  url = "/",
  store = new LiveStore(),
  session?: SessionInfo,
): RenderResult & { store: LiveStore } {
  const live = (
    <LiveProvider store={store} connect={false}>
      {ui}
    </LiveProvider>
  );
  const result = render(
    <MemoryRouter initialEntries={[url]}>
      {session ? (
        <SessionContext
          value={{ info: session, logout: () => Promise.resolve(), recheck: () => undefined }}
        >
          {live}
        </SessionContext>
      ) : (
        live
      )}
    </MemoryRouter>,
  );
  return { ...result, store };
}
