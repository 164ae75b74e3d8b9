import { useState, type ReactNode } from "react";

import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useAction } from "../../lib/useApi";
import { MODES } from "./model";
import { recommendedPdos } from "./pdoApi";
import type { Pdo } from "./types";

/** Pick the operating modes the axis will run in; the server proposes a mapping for them. */
export function ModeWizard({
  node,
  onDraft,
  onEditCurrent,
  disabled,
}: {
  node: number;
  onDraft: (pdos: Pdo[], source: string) => void;
  onEditCurrent: () => void;
  disabled: boolean;
}): ReactNode {
  const [modes, setModes] = useState<ReadonlySet<string>>(() => new Set(["pp"]));
  const recommend = useAction(async () => {
    const codes = MODES.filter((m) => modes.has(m.code)).map((m) => m.code);
    const pdos = await recommendedPdos(node, codes);
    onDraft(pdos, `recommended for ${codes.map((c) => c.toUpperCase()).join(" + ")}`);
  });

  function toggle(code: string, on: boolean): void {
    setModes((old) => {
      const next = new Set(old);
      if (on) next.add(code);
      else next.delete(code);
      return next;
    });
  }

  return (
    <section className="card" aria-labelledby="pdo-wizard-heading">
      <header className="card-header">
        <h2 id="pdo-wizard-heading">Map by purpose</h2>
        <span className="muted small">
          Choose the modes this axis runs in; the draft maps what they need to command and watch.
        </span>
      </header>
      <fieldset className="pdo-modes">
        <legend className="visually-hidden">Operating modes</legend>
        {MODES.map((mode) => (
          <label key={mode.code} className="check">
            <input
              type="checkbox"
              checked={modes.has(mode.code)}
              onChange={(e) => toggle(mode.code, e.target.checked)}
            />
            {mode.name} ({mode.code.toUpperCase()})
          </label>
        ))}
      </fieldset>
      <div className="button-row">
        <button
          type="button"
          className="primary"
          disabled={disabled || modes.size === 0 || recommend.busy}
          onClick={() => void recommend.run()}
        >
          Recommend mapping
        </button>
        <button type="button" disabled={disabled} onClick={onEditCurrent}>
          Edit current mapping
        </button>
        {recommend.busy && <Spinner label="Asking for a mapping" />}
      </div>
      <ErrorText error={recommend.error} />
    </section>
  );
}
