import type { ReactNode } from "react";

import type { ApiError } from "../api/errors";

/** An error shown where it happened; SDO aborts read "0x06010002 — Attempt to write …". */
export function ErrorText({ error }: { error: ApiError | string | null | undefined }): ReactNode {
  if (!error) return null;
  const text = typeof error === "string" ? error : error.describe();
  return (
    <p className="error-text" role="alert">
      {text}
    </p>
  );
}
