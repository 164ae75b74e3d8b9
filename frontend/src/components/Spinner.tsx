import type { ReactNode } from "react";

import { useTranslation } from "../i18n";

export function Spinner({ label }: { label?: string }): ReactNode {
  const { t } = useTranslation();
  return <span className="spinner" role="status" aria-label={label ?? t("common.working")} />;
}
