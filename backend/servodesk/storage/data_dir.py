"""Whether the data directory can hold what the app keeps (audit log, timeline, captures, logs),
asked before the server starts: a directory that cannot be written is one line to the user,
not a traceback from whichever store opens first."""

from __future__ import annotations

import errno
import tempfile
from pathlib import Path


def data_dir_problem(path: Path) -> str | None:
    """What keeps `path` from being the data directory (one line), or None."""
    try:
        path.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=path, prefix=".write-check-"):
            pass
    except OSError as error:
        reason = error.strerror or type(error).__name__
        if error.errno in (errno.ENOSPC, errno.EDQUOT):
            return (
                f"the data directory {path} has no space left ({reason}): free space there "
                "or set SERVODESK_DATA_DIR to a directory on another disk"
            )
        return (
            f"the data directory {path} cannot be written ({reason}): set SERVODESK_DATA_DIR "
            "to a directory ServoDesk may write"
        )
    return None
