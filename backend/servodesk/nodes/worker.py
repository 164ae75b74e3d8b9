"""The one thread that runs a node's blocking calls, in three lanes (nodes/session.py says
when each lane is used and why)."""

from __future__ import annotations

import asyncio
import threading
from collections import deque
from collections.abc import Callable
from contextlib import suppress
from typing import Any, Literal, TypeVar

T = TypeVar("T")


class StopCutInError(Exception):
    """Raised in a call that would write after a stop ran between its reads."""


# A call for the worker and the event-loop future its caller awaits (None: nobody waits).
# the worker's lanes, taken in this order: stops, motion commands, everything else
Lane = Literal["urgent", "command", "normal"]
LANES: tuple[Lane, ...] = ("urgent", "command", "normal")
_Item = tuple[Callable[[], Any], "asyncio.Future[Any] | None"]


class NodeWorker:
    """One thread running submitted calls one at a time, with three lanes: priority items
    (stops) are taken before everything queued so far, then commands, then normal items; each
    lane is FIFO. A normal call in progress lets stops, then commands, run between its SDO
    transfers while it has only read (`between`); a later write of that call is refused after a
    stop, not after a command (a command decides nothing the call had decided).
    A caller awaits a loop future settled by one `call_soon_threadsafe` (a wrapped concurrent
    Future cost a condition and two more callbacks per call, both sides of the hop)."""

    def __init__(self, name: str) -> None:
        self._lanes: dict[Lane, deque[_Item]] = {lane: deque() for lane in LANES}
        self._ready = threading.Condition()
        self._shutdown = False
        # what the call in progress did (worker thread only)
        self._lane: Lane = "normal"  # of the call in progress: "urgent" (a stop) runs whole
        self._wrote = False
        self._cut_in = False
        self._busy = False  # a call runs (guarded by _ready)
        self._claimed = False  # a transfer made elsewhere holds the node (`claim`)
        self._thread = threading.Thread(target=self._loop, name=name, daemon=True)
        self._thread.start()

    def submit(
        self,
        fn: Callable[[], T],
        future: asyncio.Future[T] | None = None,
        *,
        lane: Lane = "normal",
    ) -> None:
        """Queue `fn`; its result or exception goes to `future` (a cancelled one: not run)."""
        with self._ready:
            if self._shutdown:
                raise RuntimeError("the node's worker has stopped")
            self._lanes[lane].append((fn, future))
            self._ready.notify()

    def claim(self) -> bool:
        """Take the node's SDO channel for one transfer made on the loop (nodes/loop_upload.py):
        only while nothing runs or waits here; nothing starts here until `release`."""
        with self._ready:
            if self._busy or self._claimed or self._shutdown or any(self._lanes.values()):
                return False
            self._claimed = True
            return True

    def release(self) -> None:
        with self._ready:
            self._claimed = False
            self._ready.notify()

    def shutdown(self) -> None:
        """Stop after the items already queued (each of which ends at once: the session is
        closed, so `_call` refuses them)."""
        with self._ready:
            self._shutdown = True
            self._ready.notify()

    def between(self, writing: bool) -> None:
        """Called before each SDO transfer of the running call. A read lets the stops queued
        meanwhile run first; a write after such a stop raises StopCutInError."""
        if threading.get_ident() != self._thread.ident or self._lane == "urgent":
            return  # not a worker's call, or a stop itself: it runs whole
        if writing:
            if self._cut_in:
                raise StopCutInError
            self._wrote = True
            return
        if self._wrote:
            return  # a call that wrote runs to its end: the stop comes after it
        # commands keep their order: none cuts into another command
        lanes: tuple[Lane, ...] = ("urgent", "command") if self._lane == "normal" else ("urgent",)
        while True:
            with self._ready:
                taken = self._take(lanes)
            if taken is None:
                return
            (fn, future), lane = taken
            outer = (self._lane, self._wrote, self._cut_in)
            self._wrote = self._cut_in = False  # the cutting call's own
            self._execute(fn, future, lane=lane)
            self._lane, self._wrote, self._cut_in = outer
            if lane == "urgent":
                self._cut_in = True

    def _loop(self) -> None:
        while True:
            with self._ready:
                while (self._claimed or not any(self._lanes.values())) and not self._shutdown:
                    self._ready.wait()
                taken = self._take(LANES)
                self._busy = taken is not None
            if taken is None:
                return  # shut down and drained
            (fn, future), lane = taken
            self._wrote = self._cut_in = False
            try:
                self._execute(fn, future, lane=lane)
            finally:
                with self._ready:
                    self._busy = False

    def _take(self, lanes: tuple[Lane, ...]) -> tuple[_Item, Lane] | None:
        """The next item of the first of `lanes` that has one (the caller holds `_ready`)."""
        for lane in lanes:
            if self._lanes[lane]:
                return self._lanes[lane].popleft(), lane
        return None

    def _execute(
        self, fn: Callable[[], Any], future: asyncio.Future[Any] | None, *, lane: Lane
    ) -> None:
        if future is not None and future.cancelled():
            return  # its caller stopped waiting before it started
        self._lane = lane
        try:
            result = fn()
        except BaseException as error:  # handed to the awaiting caller
            _settle_from_thread(future, None, error)
        else:
            _settle_from_thread(future, result, None)
        finally:
            self._lane = "normal"


def _settle_from_thread(
    future: asyncio.Future[Any] | None, result: Any, error: BaseException | None
) -> None:
    if future is not None:
        with suppress(RuntimeError):  # the loop has closed: nobody waits any more
            future.get_loop().call_soon_threadsafe(_settle, future, result, error)


def _settle(future: asyncio.Future[Any], result: Any, error: BaseException | None) -> None:
    if future.done():  # cancelled while the call ran: its result goes nowhere
        return
    if error is None:
        future.set_result(result)
    else:
        future.set_exception(error)
