import type { ReactNode } from "react";

import { EdsCheckPanel } from "./EdsCheckPanel";

/** Tools that work on files rather than on a node. */
export function ToolsPage(): ReactNode {
  return (
    <section className="page">
      <header className="page-header">
        <h1>Tools</h1>
      </header>
      <EdsCheckPanel />
    </section>
  );
}
