"""The audit log: every write to a drive, who made it and what came of it (docs/security.md)."""

from servodesk.audit.entry import Outcome, Pending, current_entry
from servodesk.audit.log import AuditLog
from servodesk.audit.store import AuditFilter, AuditRow

__all__ = ["AuditFilter", "AuditLog", "AuditRow", "Outcome", "Pending", "current_entry"]
