import type { ReactNode } from "react";

import { homingMethods } from "../../api/driveApi";
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
  const methods = useApi((signal) => homingMethods(node, signal), `homing:${node}`);
  return (
    <label className="inline">
      Method{" "}
      <select
        value={value}
        disabled={disabled}
        aria-label="Homing method"
        onChange={(e) => onChange(e.target.value)}
      >
        <option value="">As set in the drive (6098h)</option>
        {(methods.data ?? []).map((m) => (
          <option key={m.method} value={String(m.method)}>
            {m.method}: {m.name}
          </option>
        ))}
      </select>
    </label>
  );
}
