import { useId, useRef, type ReactNode } from "react";

/** The object-dictionary files the server reads: what a dictionary upload or check accepts. */
export const OD_FILE_TYPES = ".eds,.dcf,.xdd,.xdc,.xpd";

interface Props {
  /** Visible button text and the input's accessible name ("Load EDS…"). */
  label: string;
  accept: string;
  disabled?: boolean;
  /** The button's tooltip (why it is disabled, when it is). */
  title?: string | undefined;
  onFile: (file: File) => void;
}

/**
 * A button that opens the file chooser. The real <input type=file> stays in the page (visually
 * hidden, labelled) so keyboard users, screen readers and browser tests can use it directly.
 */
export function FilePicker({ label, accept, disabled = false, title, onFile }: Props): ReactNode {
  const id = useId();
  const input = useRef<HTMLInputElement>(null);
  return (
    <span className="file-picker">
      <input
        id={id}
        ref={input}
        className="visually-hidden"
        type="file"
        accept={accept}
        aria-label={label}
        disabled={disabled}
        onChange={(event) => {
          const file = event.target.files?.[0];
          // Reset so choosing the same file again still fires a change.
          event.target.value = "";
          if (file) onFile(file);
        }}
      />
      <button
        type="button"
        disabled={disabled}
        title={title}
        onClick={() => input.current?.click()}
      >
        {label}
      </button>
    </span>
  );
}
