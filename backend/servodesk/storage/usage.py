"""How much the data directory holds, by kind, and how much its disk has left: for
`GET /api/health` and the pages that keep files (Logs, Scope). Walking the directory is done off
the loop and remembered for a few seconds (health is polled)."""

from __future__ import annotations

import asyncio
import os
import shutil
import time
from pathlib import Path

from pydantic import BaseModel

from servodesk.storage.quota import MB

FRESH_S = 5.0  # how long a measurement is served again


class DataUsage(BaseModel):
    """Bytes under the data directory, by what they are, against the quotas that keep them."""

    total_bytes: int  # everything under the data directory
    free_bytes: int  # left on its disk (for this user)
    logs_bytes: int  # decoded logs
    logs_keep_bytes: int  # beyond this the oldest decoded logs are deleted
    captures_bytes: int  # scope captures
    captures_keep_bytes: int  # beyond this the oldest finished captures are deleted
    recordings_bytes: int  # bus recordings (never deleted by the app)
    min_free_bytes: int  # a capture ends when the disk has less than this left


def directory_bytes(path: Path) -> int:
    """The bytes of every file under `path` (0 when it does not exist); files that vanish
    while counted are skipped."""
    total = 0
    for directory, _dirs, files in os.walk(path):
        for name in files:
            try:
                total += os.stat(os.path.join(directory, name), follow_symlinks=False).st_size
            except OSError:
                continue
    return total


def _file_bytes(path: Path) -> int:
    try:
        return path.lstat().st_size
    except OSError:
        return 0


def free_bytes(path: Path) -> int:
    try:
        return shutil.disk_usage(path).free
    except OSError:
        return 0


class UsageMeter:
    """Measures the data directory (`logs/`, `scope/`, `recordings/` and the rest)."""

    def __init__(
        self, root: Path, *, logs_keep_mb: int, captures_keep_mb: int, min_free_mb: int
    ) -> None:
        self.root = root
        self.logs_keep = logs_keep_mb * MB
        self.captures_keep = captures_keep_mb * MB
        self.min_free = min_free_mb * MB
        self._last: tuple[float, DataUsage] | None = None

    def measure(self) -> DataUsage:
        """Blocking: walk the directory now, once, adding each file to its top folder."""
        by_top: dict[str, int] = {}
        for top in self.root.iterdir() if self.root.is_dir() else ():
            size = directory_bytes(top) if top.is_dir() else _file_bytes(top)
            by_top[top.name] = size
        usage = DataUsage(
            total_bytes=sum(by_top.values()),
            free_bytes=free_bytes(self.root),
            logs_bytes=by_top.get("logs", 0),
            logs_keep_bytes=self.logs_keep,
            captures_bytes=by_top.get("scope", 0),
            captures_keep_bytes=self.captures_keep,
            recordings_bytes=by_top.get("recordings", 0),
            min_free_bytes=self.min_free,
        )
        self._last = (time.monotonic(), usage)
        return usage

    async def usage(self) -> DataUsage:
        """A recent measurement (at most FRESH_S old), taken off the loop when due."""
        last = self._last
        if last is not None and time.monotonic() - last[0] < FRESH_S:
            return last[1]
        return await asyncio.to_thread(self.measure)

    def forget(self) -> None:
        """Measure anew next time (files were added or deleted)."""
        self._last = None
