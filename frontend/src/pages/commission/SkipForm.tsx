import { useState, type SubmitEvent, type ReactNode } from "react";

import { useTranslation } from "../../i18n";
import { titleInSentence } from "./steps";

/** Skip needs a reason: the record says why a step was not done. */
export function SkipForm({
  title,
  busy,
  onSkip,
  onCancel,
}: {
  title: string;
  busy: boolean;
  onSkip: (reason: string) => void;
  onCancel: () => void;
}): ReactNode {
  const { t } = useTranslation();
  const [reason, setReason] = useState("");
  const ready = reason.trim() !== "";
  function submit(event: SubmitEvent): void {
    event.preventDefault();
    if (ready) onSkip(reason.trim());
  }
  return (
    <form
      className="skip-form"
      onSubmit={submit}
      aria-label={t("commission.skip.label", { title })}
    >
      <label className="block">
        {t("commission.skip.why", { step: titleInSentence(title) })}{" "}
        <span className="muted small">{t("commission.skip.required")}</span>
        <textarea
          rows={2}
          maxLength={500}
          value={reason}
          required
          aria-label={t("commission.skip.reasonLabel", { title })}
          onChange={(e) => setReason(e.target.value)}
        />
      </label>
      <div className="button-row">
        <button type="submit" disabled={!ready || busy}>
          {t("commission.skip.submit")}
        </button>
        <button type="button" className="link-button" onClick={onCancel}>
          {t("commission.cancel")}
        </button>
        {!ready && <span className="muted small">{t("commission.skip.giveReason")}</span>}
      </div>
    </form>
  );
}
