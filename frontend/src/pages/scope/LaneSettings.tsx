import type { ReactNode } from "react";

import { useTranslation, type MessageKey } from "../../i18n";
import { CONTROLWORD_BITS, STATUSWORD_BITS, toggleBit, type Lanes } from "./lanes";

function BitRow({
  title,
  bits,
  chosen,
  onChange,
}: {
  title: string;
  bits: readonly (readonly [number, MessageKey])[];
  chosen: readonly number[];
  onChange: (bits: number[]) => void;
}): ReactNode {
  const { t } = useTranslation();
  return (
    <fieldset className="scope-lanes">
      <legend>{title}</legend>
      {bits.map(([bit, name]) => (
        <label key={bit} className="scope-lane-bit">
          <input
            type="checkbox"
            checked={chosen.includes(bit)}
            onChange={() => onChange(toggleBit(chosen, bit))}
          />
          {bit} {t(name)}
        </label>
      ))}
    </fieldset>
  );
}

/** The statusword's and controlword's lanes in the recording: the state (command) always,
 * and the bits chosen here, each as its own lane under the plots. */
export function LaneSettings({
  lanes,
  onChange,
}: {
  lanes: Lanes;
  onChange: (lanes: Lanes) => void;
}): ReactNode {
  const { t } = useTranslation();
  return (
    <details className="card scope-lane-settings">
      <summary>
        <strong>{t("scope.lanes.summary")}</strong>{" "}
        <span className="muted small">
          {t("scope.lanes.hint", {
            status: lanes.statusword_bits.join(", ") || t("scope.lanes.none"),
            control: lanes.controlword_bits.join(", ") || t("scope.lanes.none"),
          })}
        </span>
      </summary>
      <BitRow
        title={t("scope.lanes.statusBits")}
        bits={STATUSWORD_BITS}
        chosen={lanes.statusword_bits}
        onChange={(statusword_bits) => onChange({ ...lanes, statusword_bits })}
      />
      <BitRow
        title={t("scope.lanes.controlBits")}
        bits={CONTROLWORD_BITS}
        chosen={lanes.controlword_bits}
        onChange={(controlword_bits) => onChange({ ...lanes, controlword_bits })}
      />
    </details>
  );
}
