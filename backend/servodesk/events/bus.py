"""The one event bus: every service publishes typed events; the timeline store, the fault
service and (hooked up by the live channel) the WebSocket subscribe.

Two ways in:
- `publish(event)` on the event loop: subscribers are called at once, in order.
- `hand_over(fn, *args)` from any thread (python-can's notifier): no I/O, no subscriber runs
  there; the call is appended to a bounded queue and the loop drains it in one
  `call_soon_threadsafe` callback per burst. A full queue drops the call and counts it; the
  count is published as a `dropped` event once the loop catches up (never silently).

Subscription point for the live channel: `remove = bus.subscribe(callback)`; `callback(event)`
runs on the event loop and must not block (hand heavy work to a task).
"""

from __future__ import annotations

import asyncio
import collections
import logging
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any

from servodesk.events.texts import Said

log = logging.getLogger(__name__)

QUEUE_LIMIT = 100_000  # calls waiting for the loop; a 1000 frames/s storm needs a few hundred


class EventKind(StrEnum):
    BOOT_UP = "boot-up"
    NODE_LOST = "node-lost"
    NODE_BACK = "node-back"
    NMT = "nmt"  # an NMT command the tool sent
    BUS = "bus"  # connected, error, disconnected
    EMCY = "emcy"  # a fault arrived (data: the Fault)
    FAULT_CLEARED = "fault-cleared"  # error-reset EMCY (code 0000h) or a fault reset that worked
    FAULT_RESET = "fault-reset"  # the tool's fault reset and its result
    SDO_ABORT = "sdo-abort"  # an abort a node sent (580h+id, command 80h)
    CIA402_STATE = "cia402-state"  # a statusword showing another CiA 402 state
    TOOL_WRITE = "tool-write"  # a write made by the tool (node, object, value)
    RECORDING = "recording"  # a raw-frame recording started or stopped
    DROPPED = "dropped"  # events lost under overload (data.count)


@dataclass(frozen=True, slots=True)
class BusEvent:
    time: float  # UNIX time
    kind: EventKind
    node: int | None
    message: str  # in words (English), for the timeline
    data: dict[str, Any] = field(default_factory=dict)  # JSON-able detail
    # the words as a message id and parameters (events/texts.py); None: English only
    message_id: str | None = None
    params: dict[str, str | int] = field(default_factory=dict)


Subscriber = Callable[[BusEvent], None]


def event(
    kind: EventKind, node: int | None, message: str | Said, data: dict[str, Any] | None = None
) -> BusEvent:
    """An event now; `message` as words said by id (`events.texts.say`) or, for a text no
    catalogue holds, in English only."""
    if isinstance(message, Said):
        said = message
        return BusEvent(
            time.time(), kind, node, said.message, data or {}, said.message_id, dict(said.params)
        )
    return BusEvent(time.time(), kind, node, message, data or {})


class EventBus:
    def __init__(self, queue_limit: int = QUEUE_LIMIT) -> None:
        self._subscribers: list[Subscriber] = []
        self._queue: collections.deque[tuple[Callable[..., None], tuple[Any, ...]]] = (
            collections.deque()
        )
        self._limit = queue_limit
        self._lock = threading.Lock()  # guards the queue length check and `_scheduled`
        self._scheduled = False
        self._loop: asyncio.AbstractEventLoop | None = None
        self.dropped = 0  # calls lost since start (a full queue)
        self._reported = 0  # dropped count already published
        self.published = 0

    def attach_loop(self) -> None:
        """Remember the running loop (thread hand-overs go to it); call on the loop."""
        self._loop = asyncio.get_running_loop()

    def subscribe(self, fn: Subscriber) -> Callable[[], None]:
        """Call `fn(event)` on the loop for every event from now on; returns its remover."""
        self._subscribers.append(fn)

        def remove() -> None:
            if fn in self._subscribers:
                self._subscribers.remove(fn)

        return remove

    def publish(self, item: BusEvent) -> None:
        """On the event loop: every subscriber sees `item` now."""
        self.published += 1
        for fn in list(self._subscribers):
            try:
                fn(item)
            except Exception:
                log.exception("event subscriber failed")  # one must not starve the others

    def hand_over(self, fn: Callable[..., None], *args: Any) -> None:
        """From any thread: run `fn(*args)` on the loop soon. Never blocks, never does I/O."""
        loop = self._loop
        if loop is None or loop.is_closed():
            return
        with self._lock:
            if len(self._queue) >= self._limit:
                self.dropped += 1
                return
            self._queue.append((fn, args))
            if self._scheduled:
                return
            self._scheduled = True
        try:
            loop.call_soon_threadsafe(self._drain)
        except RuntimeError:  # the loop closed meanwhile (shutdown)
            with self._lock:
                self._scheduled = False

    def _drain(self) -> None:
        with self._lock:
            self._scheduled = False
            batch = list(self._queue)
            self._queue.clear()
        for fn, args in batch:
            try:
                fn(*args)
            except Exception:
                log.exception("handed-over call failed")
        if self.dropped != self._reported:
            lost = self.dropped - self._reported
            self._reported = self.dropped
            self.publish(
                event(
                    EventKind.DROPPED,
                    None,
                    f"{lost} events were dropped under overload ({self.dropped} since start)",
                    {"count": lost, "total": self.dropped},
                )
            )
