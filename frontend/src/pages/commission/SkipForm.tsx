import { useState, type SubmitEvent, type ReactNode } from "react";

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
  const [reason, setReason] = useState("");
  const ready = reason.trim() !== "";
  function submit(event: SubmitEvent): void {
    event.preventDefault();
    if (ready) onSkip(reason.trim());
  }
  return (
    <form className="skip-form" onSubmit={submit} aria-label={`Skip ${title}`}>
      <label className="block">
        Why is {title.toLowerCase()} skipped? <span className="muted small">(required)</span>
        <textarea
          rows={2}
          maxLength={500}
          value={reason}
          required
          aria-label={`Reason to skip ${title}`}
          onChange={(e) => setReason(e.target.value)}
        />
      </label>
      <div className="button-row">
        <button type="submit" disabled={!ready || busy}>
          Skip step
        </button>
        <button type="button" className="link-button" onClick={onCancel}>
          Cancel
        </button>
        {!ready && <span className="muted small">Give a reason to skip.</span>}
      </div>
    </form>
  );
}
