// Render a page inside the providers the app gives it: a router at `url` and a live store with
// no WebSocket (tests fill the store themselves).
import { render, type RenderResult } from "@testing-library/react";
import type { ReactNode } from "react";
import { MemoryRouter } from "react-router";

import { LiveProvider } from "../live/LiveProvider";
import { LiveStore } from "../live/store";

export function renderPage(
  ui: ReactNode,
  url = "/",
  store = new LiveStore(),
): RenderResult & { store: LiveStore } {
  const result = render(
    <MemoryRouter initialEntries={[url]}>
      <LiveProvider store={store} connect={false}>
        {ui}
      </LiveProvider>
    </MemoryRouter>,
  );
  return { ...result, store };
}
