import { useCallback, useEffect, useMemo, useState, type ReactNode } from "react";

import { asApiError, onUnauthorized, type ApiError } from "../api/errors";
import { ErrorText } from "../components/ErrorText";
import { Spinner } from "../components/Spinner";
import { useTranslation } from "../i18n";
import { SessionContext, type SessionControl } from "./context";
import { LoginScreen } from "./LoginScreen";
import { fetchSession, logOut } from "./sessionApi";
import type { SessionInfo } from "./types";

type GateState =
  | { status: "loading" }
  | { status: "login" }
  | { status: "ready"; info: SessionInfo }
  | { status: "failed"; error: ApiError };

/**
 * Asks the server who this browser is before anything else loads. When a login is needed (at
 * start, or a 401 from any request later) the login screen replaces the app; the URL stays, so
 * after logging in the user is back on the page they were on. The app below, with its live
 * socket, mounts only with a session: a fresh login starts a fresh connection.
 */
export function SessionGate({ children }: { children: ReactNode }): ReactNode {
  const { t } = useTranslation();
  const [state, setState] = useState<GateState>({ status: "loading" });
  const [nonce, setNonce] = useState(0);

  useEffect(() => {
    let alive = true;
    fetchSession().then(
      (info) => {
        if (alive) setState({ status: "ready", info });
      },
      (caught: unknown) => {
        const error = asApiError(caught);
        if (alive)
          setState(error.status === 401 ? { status: "login" } : { status: "failed", error });
      },
    );
    return () => {
      alive = false;
    };
  }, [nonce]);

  useEffect(
    () => onUnauthorized(() => setState((s) => (s.status === "login" ? s : { status: "login" }))),
    [],
  );

  const recheck = useCallback(() => setNonce((n) => n + 1), []);
  const logout = useCallback(async () => {
    await logOut();
    setState({ status: "login" });
  }, []);
  const info = state.status === "ready" ? state.info : null;
  const control = useMemo<SessionControl | null>(
    () => (info ? { info, logout, recheck } : null),
    [info, logout, recheck],
  );

  switch (state.status) {
    case "loading":
      return (
        <div className="session-screen">
          <Spinner label={t("session.connecting")} />
        </div>
      );
    case "failed":
      return (
        <div className="session-screen">
          <div className="card login-card">
            <h1>ServoDesk</h1>
            <ErrorText error={state.error} />
            <button type="button" onClick={recheck}>
              {t("session.tryAgain")}
            </button>
          </div>
        </div>
      );
    case "login":
      return <LoginScreen onLoggedIn={(next) => setState({ status: "ready", info: next })} />;
    case "ready":
      return <SessionContext value={control}>{children}</SessionContext>;
  }
}
