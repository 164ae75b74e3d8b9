import type { ReactNode } from "react";

import { CONTROLWORD_BITS, STATUSWORD_BITS, toggleBit, type Lanes } from "./lanes";

function BitRow({
  title,
  bits,
  chosen,
  onChange,
}: {
  title: string;
  bits: readonly (readonly [number, string])[];
  chosen: readonly number[];
  onChange: (bits: number[]) => void;
}): ReactNode {
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
          {bit} {name}
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
  return (
    <details className="card scope-lane-settings">
      <summary>
        <strong>Word lanes</strong>{" "}
        <span className="muted small">
          statusword 6041h: the CiA 402 state and bits {lanes.statusword_bits.join(", ") || "none"};
          controlword 6040h: the command and bits {lanes.controlword_bits.join(", ") || "none"}
        </span>
      </summary>
      <BitRow
        title="Statusword 6041h bits"
        bits={STATUSWORD_BITS}
        chosen={lanes.statusword_bits}
        onChange={(statusword_bits) => onChange({ ...lanes, statusword_bits })}
      />
      <BitRow
        title="Controlword 6040h bits"
        bits={CONTROLWORD_BITS}
        chosen={lanes.controlword_bits}
        onChange={(controlword_bits) => onChange({ ...lanes, controlword_bits })}
      />
    </details>
  );
}
