import type { ReactNode } from "react";

/** A labelled number input that marks itself invalid and says why in its tooltip. */
export function NumberField({
  label,
  value,
  onChange,
  error,
  title,
  id,
}: {
  label: string;
  value: string;
  onChange: (value: string) => void;
  error: string | null;
  title?: string;
  id?: string;
}): ReactNode {
  return (
    <label title={title} htmlFor={id}>
      <span>{label}</span>
      <input
        id={id}
        className="narrow"
        inputMode="decimal"
        aria-invalid={error !== null}
        title={error ?? undefined}
        value={value}
        onChange={(e) => onChange(e.target.value)}
      />
    </label>
  );
}
