import type { ReactNode } from "react";

import { ErrorText } from "../components/ErrorText";
import { useTranslation, type MessageKey } from "../i18n";
import { useAction } from "../lib/useApi";
import { useSessionControl } from "./context";
import type { Role } from "./types";

const ROLE_NAME: Record<Role, MessageKey> = {
  viewer: "session.roleName.viewer",
  operator: "session.roleName.operator",
  engineer: "session.roleName.engineer",
};

/** "engineer · engineer" and Log out, in the sidebar; nothing on a server without logins. */
export function SessionBadge(): ReactNode {
  const { t } = useTranslation();
  const session = useSessionControl();
  const logout = useAction(async () => {
    await session?.logout();
  });
  if (!session?.info.auth_required) return null;
  const { user, role } = session.info;
  return (
    <div className="session-badge">
      <span
        className="session-user"
        data-testid="session-user"
        title={t("session.loggedInAs", { user })}
      >
        {t("session.userRole", { user, role: t(ROLE_NAME[role]) })}
      </span>
      <button
        type="button"
        className="small"
        disabled={logout.busy}
        onClick={() => void logout.run()}
      >
        {t("session.logOut")}
      </button>
      <ErrorText error={logout.error} inline />
    </div>
  );
}
