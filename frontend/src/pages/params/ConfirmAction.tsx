import { useState, type ReactNode } from "react";

import { Dialog } from "../../components/Dialog";
import { ErrorText } from "../../components/ErrorText";
import { Spinner } from "../../components/Spinner";
import { useTranslation } from "../../i18n";
import { useAction } from "../../lib/useApi";

interface Props {
  /** Button text that opens the dialog; also the dialog's title. */
  label: string;
  /** What will happen, in words, shown before the user confirms. */
  explanation: ReactNode;
  confirmLabel: string;
  disabled?: boolean;
  /** The opening button's tooltip (why it is disabled, when it is). */
  title?: string | undefined;
  /** Runs on confirm; returns the server's message, or null when the page shows the outcome. */
  onConfirm: () => Promise<string | null>;
}

/** A button that asks before it acts, then shows the server's answer. */
export function ConfirmAction({
  label,
  explanation,
  confirmLabel,
  disabled = false,
  title,
  onConfirm,
}: Props): ReactNode {
  const { t } = useTranslation();
  const [open, setOpen] = useState(false);
  const [message, setMessage] = useState<string | null>(null);
  const action = useAction(async () => {
    setMessage(await onConfirm());
    setOpen(false);
  });
  return (
    <>
      <button
        type="button"
        disabled={disabled}
        title={title}
        onClick={() => {
          action.clearError();
          setOpen(true);
        }}
      >
        {label}
      </button>
      {message && (
        <span className="note small" role="status">
          {message}
        </span>
      )}
      {open && (
        <Dialog
          title={label}
          onClose={() => setOpen(false)}
          actions={
            <>
              <button type="button" onClick={() => setOpen(false)}>
                {t("params.cancel")}
              </button>
              <button
                type="button"
                className="primary"
                disabled={action.busy}
                onClick={() => void action.run()}
              >
                {confirmLabel}
              </button>
              {action.busy && <Spinner />}
            </>
          }
        >
          {explanation}
          <ErrorText error={action.error} />
        </Dialog>
      )}
    </>
  );
}
