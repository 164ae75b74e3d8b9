// The login session as GET /api/session describes it.
import type { components } from "../api/schema";

export type SessionInfo = components["schemas"]["SessionInfo"];

export type Role = SessionInfo["role"];

/** What a role may do beyond reading: run the drives, or change their configuration. */
export type Permission = keyof SessionInfo["may"];
