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


def _decode(
    data_dir: Path, path: Path, dcf: Path | None, profiles: dict[int, str] | None = None
) -> LogResult:
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
    milliseconds from the fork server)."""

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
                initializer=lower_priority,  # below the server: a stop must not wait for a core
                max_tasks_per_child=1,
            )
        return self._pool

    def close(self) -> None:
        pool, self._pool = self._pool, None
        if pool is not None:
            shut_down_aside(pool, "log-decode-shutdown")
