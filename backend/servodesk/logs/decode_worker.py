"""Decoding an uploaded log in a process of its own.

A large log is CPU work for seconds to minutes. In a thread of the server it holds the
interpreter lock most of that time: the event loop, the nodes' workers sending stops and the
tool's heartbeat thread all wait for it. So each decode runs in a short-lived worker process
that writes the result's SQLite file itself; only the small LogResult comes back.

The workers fork from the same server process as the dictionary parses (od/parser.py), which
keeps asammdf out (od/parse_worker.py); a log decode needs it for .mf4, so it is let back in.
"""

from __future__ import annotations

import asyncio
import importlib
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from servodesk.logs.blf import LogBoundsError
from servodesk.logs.store import LogResult, LogStore
from servodesk.od.parser import lower_priority, shut_down_aside, worker_context

PRELOAD = ["servodesk.od.parse_worker", "servodesk.od.parser"]  # as od/parser.py: one server


class LogReadError(Exception):
    """The reader's complaint about the file, as words (any exception type pickles as this)."""


class LogRefusedError(LogReadError):
    """The file was refused unread: it declares or expands to sizes no real log has."""


# A log up to this size decodes in about a second at most (a compressed BLF: some 50,000
# frames): at the server's own priority, so a busy host (other programs at full CPU) cannot
# starve it for tens of seconds; a larger one is bulk work and yields the CPU to the server
# that stops the drives.
SMALL_LOG_BYTES = 256 * 1024


def _decode(
    data_dir: Path, path: Path, dcf: Path | None, profiles: dict[int, str] | None = None
) -> LogResult:
    if path.stat().st_size > SMALL_LOG_BYTES:
        lower_priority()
    if path.suffix.lower() == ".mf4":  # asammdf is a second of imports: only where it reads
        _let_mf4_back()
    try:
        return LogStore(data_dir).decode_file(path, dcf=dcf, profiles=profiles)
    except LogBoundsError as error:
        raise LogRefusedError(str(error)) from None
    except Exception as error:  # any reader's complaint about a user's file
        raise LogReadError(str(error) or type(error).__name__) from None


def _let_mf4_back() -> None:
    if "asammdf" in sys.modules and sys.modules["asammdf"] is None:
        del sys.modules["asammdf"]
        mf4 = sys.modules.get("can.io.mf4")
        if mf4 is not None:
            importlib.reload(mf4)  # its reader class sees the module's globals, now with asammdf


class DecodePool:
    """At most `parallel` worker processes; the pool goes when idle (a new one starts in
    milliseconds from the fork server). A worker lowers its own priority for a large log
    (`_decode`)."""

    def __init__(self, parallel: int) -> None:
        self._parallel = parallel
        self._pool: ProcessPoolExecutor | None = None
        self._running = 0

    async def decode(
        self,
        data_dir: Path,
        path: Path,
        dcf: Path | None,
        profiles: dict[int, str] | None = None,
    ) -> LogResult:
        self._running += 1
        try:
            # submitted from a thread: submit() starts the worker process (od/parser.py)
            pool = self._executor()
            future = await asyncio.to_thread(pool.submit, _decode, data_dir, path, dcf, profiles)
            return await asyncio.wrap_future(future)
        finally:
            self._running -= 1
            if self._running == 0:
                self.close()

    def _executor(self) -> ProcessPoolExecutor:
        if self._pool is None:
            context = worker_context(PRELOAD)
            self._pool = ProcessPoolExecutor(
                max_workers=self._parallel,
                mp_context=context,
                max_tasks_per_child=1,  # one decode per process: its priority goes with it
            )
        return self._pool

    def close(self) -> None:
        pool, self._pool = self._pool, None
        if pool is not None:
            shut_down_aside(pool, "log-decode-shutdown")
