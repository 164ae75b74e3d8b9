import { useState, type ReactNode } from "react";

import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { type MessageKey, useTranslation } from "../../i18n";
import { useAction } from "../../lib/useApi";
import { MODES, type ModeChoice } from "./model";
import { recommendedPdos } from "./pdoApi";
import type { Pdo } from "./types";

const MODE_NAMES: Readonly<Record<ModeChoice["code"], MessageKey>> = {
  pp: "pdo.mode.pp",
  pv: "pdo.mode.pv",
  pt: "pdo.mode.pt",
  hm: "pdo.mode.hm",
  ip: "pdo.mode.ip",
};

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
  const { t } = useTranslation();
  const [modes, setModes] = useState<ReadonlySet<string>>(() => new Set(["pp"]));
  const recommend = useAction(async () => {
    const codes = MODES.filter((m) => modes.has(m.code)).map((m) => m.code);
    const pdos = await recommendedPdos(node, codes);
    onDraft(
      pdos,
      t("pdo.wizard.recommendedFor", { modes: codes.map((c) => c.toUpperCase()).join(" + ") }),
    );
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
        <h2 id="pdo-wizard-heading">{t("pdo.wizard.heading")}</h2>
        <span className="muted small">{t("pdo.wizard.intro")}</span>
      </header>
      <fieldset className="pdo-modes">
        <legend className="visually-hidden">{t("pdo.wizard.modes")}</legend>
        {MODES.map((mode) => (
          <label key={mode.code} className="check">
            <input
              type="checkbox"
              checked={modes.has(mode.code)}
              onChange={(e) => toggle(mode.code, e.target.checked)}
            />
            {t(MODE_NAMES[mode.code])} ({mode.code.toUpperCase()})
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
          {t("pdo.wizard.recommend")}
        </button>
        <button type="button" disabled={disabled} onClick={onEditCurrent}>
          {t("pdo.wizard.editCurrent")}
        </button>
        {recommend.busy && <Spinner label={t("pdo.wizard.asking")} />}
      </div>
      <ErrorText error={recommend.error} />
    </section>
  );
}
