"""The audit log cannot be written (disk full, read-only, I/O error): the words a user sees.

A write that needs its entry first is refused with nothing sent (API 507/503 audit_unavailable);
a stop or disable goes out anyway and its answer says that it is not recorded
(docs/security.md, "When the audit log cannot be written")."""

from __future__ import annotations

import errno
import shutil
import sqlite3
from pathlib import Path

from servodesk.errors import ServodeskError, StateConflictError


class AuditUnavailableError(ServodeskError):
    def __init__(self, cause: str, data_dir: Path, *, full: bool, sent: str | None = None) -> None:
        self.cause = cause  # SQLite's or the OS's words: "database or disk is full"
        self.data_dir = data_dir
        self.full = full  # no space left: the API answers 507, otherwise 503
        self.sent = sent  # what went out unrecorded (a stop); None: nothing was sent
        # the path stays in the server log: a remote client need not learn the server's layout
        fix = (
            "free space in ServoDesk's data directory"
            if full
            else "check ServoDesk's data directory (space, permissions; the server log names it)"
        )
        if sent is None:
            text = (
                f"the audit log cannot be written ({cause}), so nothing was sent: {fix} and try "
                "again (stops and disables still work)"
            )
        else:
            text = f"{sent} was sent, but the audit log cannot be written ({cause}): {fix}"
        super().__init__(text)

    def after(self, sent: str) -> AuditUnavailableError:
        """The same failure, for a write that went out regardless."""
        return AuditUnavailableError(self.cause, self.data_dir, full=self.full, sent=sent)


def unavailable(error: BaseException, data_dir: Path) -> AuditUnavailableError:
    """A SQLite or OS error of the audit store as the user's error."""
    if isinstance(error, AuditUnavailableError):
        return error
    full = False
    if isinstance(error, sqlite3.Error):
        full = getattr(error, "sqlite_errorcode", None) == sqlite3.SQLITE_FULL
    elif isinstance(error, OSError):
        full = error.errno in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG)
    cause = str(error) or type(error).__name__
    return AuditUnavailableError(
        cause, data_dir, full=full or "full" in cause or _no_space(data_dir)
    )


def _no_space(data_dir: Path) -> bool:
    """SQLite names a full disk "disk I/O error" when it cannot create its shared-memory file."""
    try:
        return shutil.disk_usage(data_dir).free == 0
    except OSError:
        return False


class AlreadyUndoneError(StateConflictError):
    """An entry is undone once: another undo of it succeeded or is running (API 409)."""

    def __init__(self, entry: int, undo: int, user: str, result: str) -> None:
        self.entry, self.undo, self.user = entry, undo, user
        how = "is being undone" if result == "pending" else "was already undone"
        super().__init__(
            "already_undone",
            f"entry {entry} {how} by entry {undo} ({user}), so nothing was written; an entry is "
            f"undone once (undo entry {undo} to reverse that undo)",
        )
