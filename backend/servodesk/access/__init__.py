"""Who may do what: access tokens per role, login sessions, the route policy and the acting
user carried to the audit log (docs/security.md)."""

from servodesk.access.actor import SYSTEM, Actor, Role, acting, current_actor

__all__ = ["SYSTEM", "Actor", "Role", "acting", "current_actor"]
