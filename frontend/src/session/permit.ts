// Which controls a role may use, and the words for why not. The server enforces the same
// rules (403); the app disables what would be refused and says so in the control's title.
import { i18n, type MessageKey } from "../i18n";
import type { Permission, Role, SessionInfo } from "./types";

/** Everyone on a server without tokens: the loopback default. */
export const LOCAL_SESSION: SessionInfo = {
  user: "local",
  role: "engineer",
  auth_required: false,
  may: { operate: true, configure: true },
};

export interface Permit {
  allowed: boolean;
  /** The reason a control is off, e.g. "Viewer role: read only — log in as …"; undefined when
   * allowed. `doing` finishes the sentence, in the current language: "enable the drive". */
  because: (doing: string) => string | undefined;
  /** `disabled` and `title` for a control: off with the reason when not allowed, otherwise the
   * control's own state and title. */
  gate: (
    doing: string,
    own?: { disabled?: boolean; title?: string },
  ) => { disabled: boolean; title: string | undefined };
}

const ROLE_LIMIT: Record<Role, MessageKey> = {
  viewer: "session.roleLimit.viewer",
  operator: "session.roleLimit.operator",
  engineer: "session.roleLimit.engineer",
};

const WHO_MAY: Record<Permission, MessageKey> = {
  operate: "session.whoMay.operate",
  configure: "session.whoMay.configure",
};

export function permit(session: SessionInfo, need: Permission): Permit {
  const allowed = session.may[need];
  const because = (doing: string): string | undefined =>
    allowed
      ? undefined
      : i18n.t("session.because", {
          role: i18n.t(ROLE_LIMIT[session.role]),
          who: i18n.t(WHO_MAY[need]),
          doing,
        });
  return {
    allowed,
    because,
    gate: (doing, own = {}) => ({
      disabled: !allowed || (own.disabled ?? false),
      title: because(doing) ?? own.title,
    }),
  };
}
