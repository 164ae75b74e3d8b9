"""How late the event loop runs (DESIGN: the loop keeps lag p99 <= 20 ms).

A task on the loop asks to wake every TICK s and records how late it woke: the loop's lag, kept
for the last minute and reported in `GET /api/health`. A thread beside it notices a stall while
it lasts: once the loop has been silent for `stall_ms`, it logs what the loop's thread is
running right then (the Python stack: the callback that holds the loop, or the call waiting for
the interpreter lock), which is where a stall is found rather than guessed. A garbage
collection that long (it stops every thread) is logged with its generation.
"""

from __future__ import annotations

import asyncio
import contextlib
import gc
import logging
import sys
import threading
import time
import traceback
from collections import deque
from pathlib import Path

from pydantic import BaseModel, Field

log = logging.getLogger(__name__)

TICK = 0.05  # s
WINDOW = 60.0  # s of samples kept
STACK_FRAMES = 6  # innermost frames named in a stall's log line


class LoopLag(BaseModel):
    """The event loop's lag over the last minute: how late a timer of the loop ran."""

    p50_ms: float
    p99_ms: float
    max_ms: float
    samples: int = Field(description="timer wake-ups measured (one every 50 ms)")
    window_s: float


class LoopWatch:
    def __init__(self, *, stall_ms: float = 100.0) -> None:
        self._stall = stall_ms / 1000
        self._samples: deque[tuple[float, float]] = deque()  # (monotonic, lag s)
        self.last_tick = time.monotonic()  # read by the stall thread
        self._task: asyncio.Task[None] | None = None
        self._thread: threading.Thread | None = None
        self._loop_thread = 0
        self._closed = threading.Event()
        self._gc_started = 0.0

    def start(self) -> None:
        gc.callbacks.append(self._on_gc)
        self._loop_thread = threading.get_ident()
        self.last_tick = time.monotonic()
        self._task = asyncio.get_running_loop().create_task(self._run(), name="loop-watch")
        self._thread = threading.Thread(target=self._watch, name="loop-stall-watch", daemon=True)
        self._thread.start()

    async def close(self) -> None:
        with contextlib.suppress(ValueError):
            gc.callbacks.remove(self._on_gc)
        self._closed.set()
        task, self._task = self._task, None
        if task is not None:
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await task
        if self._thread is not None:
            await asyncio.to_thread(self._thread.join)

    def lag(self) -> LoopLag:
        now = time.monotonic()
        self._forget(now)
        values = sorted(lag for _, lag in self._samples)
        if not values:
            return LoopLag(p50_ms=0, p99_ms=0, max_ms=0, samples=0, window_s=WINDOW)

        def at(q: float) -> float:
            return round(values[min(len(values) - 1, round(q * (len(values) - 1)))] * 1000, 1)

        return LoopLag(
            p50_ms=at(0.5), p99_ms=at(0.99), max_ms=at(1.0), samples=len(values), window_s=WINDOW
        )

    async def _run(self) -> None:
        due = time.monotonic() + TICK
        while True:
            await asyncio.sleep(max(0.0, due - time.monotonic()))
            now = time.monotonic()
            self._samples.append((now, max(0.0, now - due)))
            self.last_tick = now
            self._forget(now)
            due = now + TICK

    def _forget(self, now: float) -> None:
        while self._samples and self._samples[0][0] < now - WINDOW:
            self._samples.popleft()

    def _watch(self) -> None:
        """Thread: name what the loop runs when it has been silent for `stall_ms`."""
        reported = 0.0  # the tick of the stall last reported: one line per stall
        while not self._closed.wait(self._stall / 4):
            tick = self.last_tick
            silent = time.monotonic() - tick - TICK
            if silent < self._stall or tick == reported:
                continue
            reported = tick
            frame = sys._current_frames().get(self._loop_thread)
            where = "?"
            if frame is not None:
                stack = traceback.extract_stack(frame)[-STACK_FRAMES:]
                where = " <- ".join(
                    f"{f.name} ({Path(f.filename).name}:{f.lineno})" for f in reversed(stack)
                )
            log.warning("event loop stalled for %.0f ms so far, running: %s", silent * 1000, where)

    def _on_gc(self, phase: str, info: dict[str, int]) -> None:
        """Any thread (the one that allocated): time each collection; log a long one."""
        if phase == "start":
            self._gc_started = time.perf_counter()
            return
        took = time.perf_counter() - self._gc_started
        if took >= self._stall / 2:
            log.warning(
                "garbage collection of generation %d took %.0f ms (%d collected)",
                info["generation"],
                took * 1000,
                info["collected"],
            )
