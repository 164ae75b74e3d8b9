"""One python-can listener that picks out the frames several services act on, once for all of
them: EMCY (80h + node id, ids 1–127) and SDO aborts (580h + node id, command byte 80h).

`BusManager` owns one (`bus.frames`) and registers it among its frame listeners, so it follows
every reconnect. Services subscribe with `on_emcy(fn)` / `on_sdo_abort(fn)`, each returning its
remover; `fn(node, data)` gets the node id and the frame's data bytes.

Subscribers run on python-can's notifier thread (docs/architecture.md, rule 2): they must not
block, do I/O or decode; they only record or hand the item to the loop
(`loop.call_soon_threadsafe`, `EventBus.hand_over`). A subscriber that raises is logged once
and counted; the frame still reaches the others and the notifier keeps running.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable

import can

from servodesk_protocol.cob_id import EMCY, MAX_NODE_ID, SDO_TX
from servodesk_protocol.sdo import ABORT_COMMAND

log = logging.getLogger(__name__)

FrameSubscriber = Callable[[int, bytes], None]  # (node id, data) on the notifier thread


class _Subscribers:
    """Callables replaced as a whole, never mutated, so the notifier thread iterates a stable
    tuple while the loop adds or removes one."""

    def __init__(self) -> None:
        self.all: tuple[FrameSubscriber, ...] = ()
        self._lock = threading.Lock()  # between two changes at once

    def add(self, fn: FrameSubscriber, *, first: bool = False) -> Callable[[], None]:
        with self._lock:
            self.all = (fn, *self.all) if first else (*self.all, fn)

        def remove() -> None:
            with self._lock:
                kept = list(self.all)
                if fn in kept:
                    kept.remove(fn)
                    self.all = tuple(kept)

        return remove

    def clear(self) -> None:
        with self._lock:
            self.all = ()


class FrameTap(can.Listener):
    """Notifier thread: recognise EMCY and SDO-abort frames and pass them to the subscribers."""

    def __init__(self) -> None:
        self._emcy = _Subscribers()
        self._aborts = _Subscribers()
        self._failed: set[FrameSubscriber] = set()
        self.failures = 0  # calls of a subscriber that raised

    def on_emcy(self, fn: FrameSubscriber, *, first: bool = False) -> Callable[[], None]:
        """Call `fn(node, data)` for every EMCY; `first` puts it ahead of the earlier
        subscribers (a stop that must not wait behind another's hand-over). Returns its
        remover. `fn` runs on the notifier thread and must not block."""
        return self._emcy.add(fn, first=first)

    def on_sdo_abort(self, fn: FrameSubscriber) -> Callable[[], None]:
        """Call `fn(node, data)` for every SDO abort a node sends (580h + node, byte 0 = 80h).
        Returns its remover. `fn` runs on the notifier thread and must not block."""
        return self._aborts.add(fn)

    def clear(self) -> None:
        """Forget every subscriber (the bus manager's shutdown)."""
        self._emcy.clear()
        self._aborts.clear()

    def on_message_received(self, msg: can.Message) -> None:
        if msg.is_error_frame or msg.is_remote_frame or msg.is_extended_id:
            return
        can_id = msg.arbitration_id
        if EMCY < can_id <= EMCY + MAX_NODE_ID:
            subscribers, node = self._emcy.all, can_id - EMCY
        elif SDO_TX < can_id <= SDO_TX + MAX_NODE_ID and msg.data and msg.data[0] == ABORT_COMMAND:
            subscribers, node = self._aborts.all, can_id - SDO_TX
        else:
            return
        data = bytes(msg.data)
        for fn in subscribers:
            try:
                fn(node, data)
            except Exception:
                self.failures += 1
                if fn not in self._failed:  # once per subscriber: a storm must not log a storm
                    self._failed.add(fn)
                    log.exception("frame subscriber %r failed on CAN id %03Xh", fn, can_id)

    def stop(self) -> None:
        """Nothing to release: the tap outlives each connection's notifier."""
