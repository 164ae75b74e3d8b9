import { useId, useState, type SubmitEvent, type ReactNode } from "react";

import type { ApiError } from "../api/errors";
import { LanguageSelect } from "../components/LanguageSelect";
import { i18n, useTranslation } from "../i18n";
import { useAction } from "../lib/useApi";
import { logIn } from "./sessionApi";
import type { SessionInfo } from "./types";

/** A refused login in words: the server's own message would not say what to do next. */
export function loginErrorText(error: ApiError): string {
  if (error.kind === "rate_limited") {
    const wait = error.retryAfterS ?? 60;
    return i18n.t("session.login.rateLimited", { seconds: wait });
  }
  if (error.status === 401) return i18n.t("session.login.wrongToken");
  return error.describe();
}

/** The server has access tokens configured: one token is one role (viewer, operator,
 * engineer). The token goes to the server once; it answers with an HttpOnly cookie. */
export function LoginScreen({
  onLoggedIn,
}: {
  onLoggedIn: (info: SessionInfo) => void;
}): ReactNode {
  const { t } = useTranslation();
  const id = useId();
  const [token, setToken] = useState("");
  const login = useAction(async (value: string) => {
    onLoggedIn(await logIn(value));
  });

  function submit(event: SubmitEvent): void {
    event.preventDefault();
    if (token.trim()) void login.run(token.trim());
  }

  return (
    <div className="session-screen">
      <form className="card login-card" onSubmit={submit} aria-labelledby={`${id}-title`}>
        <div className="brand login-brand">
          <span className="brand-mark" aria-hidden="true">
            ◎
          </span>
          ServoDesk
        </div>
        <h1 id={`${id}-title`}>{t("session.login.title")}</h1>
        <p className="muted">{t("session.login.intro")}</p>
        <label htmlFor={`${id}-token`}>{t("session.login.token")}</label>
        <input
          id={`${id}-token`}
          type="password"
          autoComplete="current-password"
          value={token}
          aria-invalid={login.error ? true : undefined}
          onChange={(e) => {
            setToken(e.target.value);
            login.clearError();
          }}
        />
        {login.error && (
          <p className="error-text" role="alert">
            {loginErrorText(login.error)}
          </p>
        )}
        <div className="button-row">
          <button type="submit" className="primary" disabled={login.busy || !token.trim()}>
            {t("session.login.submit")}
          </button>
        </div>
        <LanguageSelect className="login-language" />
      </form>
    </div>
  );
}
