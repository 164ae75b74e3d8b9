import type { ReactNode } from "react";

import { homingMethods } from "../../api/driveApi";
import { useTranslation } from "../../i18n";
import { useApi } from "../../lib/useApi";

/** The homing step's method: the drive's own (6098h) unless one of its methods is chosen. */
export function HomingMethodInput({
  node,
  value,
  disabled,
  onChange,
}: {
  node: number;
  value: string;
  disabled: boolean;
  onChange: (value: string) => void;
}): ReactNode {
  const { t } = useTranslation();
  const methods = useApi((signal) => homingMethods(node, signal), `homing:${node}`);
  return (
    <label className="inline">
      {t("commission.run.method")}{" "}
      <select
        value={value}
        disabled={disabled}
        aria-label={t("commission.run.methodLabel")}
        onChange={(e) => onChange(e.target.value)}
      >
        <option value="">{t("commission.run.methodAsSet")}</option>
        {(methods.data ?? []).map((m) => (
          <option key={m.method} value={String(m.method)}>
            {m.method}: {m.name}
          </option>
        ))}
      </select>
    </label>
  );
}
