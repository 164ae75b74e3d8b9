import type { ReactNode } from "react";

import { ErrorText } from "../components/ErrorText";
import { useAction } from "../lib/useApi";
import { useSessionControl } from "./context";

/** "engineer · engineer" and Log out, in the sidebar; nothing on a server without logins. */
export function SessionBadge(): ReactNode {
  const session = useSessionControl();
  const logout = useAction(async () => {
    await session?.logout();
  });
  if (!session?.info.auth_required) return null;
  const { user, role } = session.info;
  return (
    <div className="session-badge">
      <span className="session-user" data-testid="session-user" title={`Logged in as ${user}`}>
        {user} · {role}
      </span>
      <button
        type="button"
        className="small"
        disabled={logout.busy}
        onClick={() => void logout.run()}
      >
        Log out
      </button>
      <ErrorText error={logout.error} inline />
    </div>
  );
}
