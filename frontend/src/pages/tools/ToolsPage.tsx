import type { ReactNode } from "react";

import { useTranslation } from "../../i18n";
import { EdsCheckPanel } from "./EdsCheckPanel";

/** Tools that work on files rather than on a node. */
export function ToolsPage(): ReactNode {
  const { t } = useTranslation();
  return (
    <section className="page">
      <header className="page-header">
        <h1>{t("logs.tools.heading")}</h1>
      </header>
      <EdsCheckPanel />
    </section>
  );
}
