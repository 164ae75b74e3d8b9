"""SYNC frames another producer sends (the machine's controller): heard on the bus.

A `can.Listener` on the bus manager's notifier (every connection): frames ServoDesk sends
itself never come back through receive, so every 080h frame seen here is someone else's SYNC.
Runs on the notifier thread: it only counts and stamps under a small lock (DESIGN rule 1).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import can

from servodesk_protocol import cob_id

SYNC_ID = cob_id.SYNC  # default COB-ID of 1005h
HEARD_WITHIN_S = 2.0  # a SYNC this recent counts as a running producer (periods up to ~1 s)
US = 1_000_000


@dataclass(frozen=True)
class HeardSync:
    frames: int  # since ServoDesk started
    age_s: float | None  # since the last one; None before the first
    period_us: int | None  # between the last two; None below two frames

    @property
    def recent(self) -> bool:
        return self.age_s is not None and self.age_s <= HEARD_WITHIN_S


class SyncHeard(can.Listener):
    def __init__(self, clock: Callable[[], float] = time.monotonic) -> None:
        self._clock = clock
        self._lock = threading.Lock()
        self._frames = 0
        self._last: float | None = None
        self._previous: float | None = None

    def on_message_received(self, msg: can.Message) -> None:
        if (
            msg.arbitration_id != SYNC_ID
            or msg.is_extended_id
            or msg.is_error_frame
            or msg.is_remote_frame
            or not msg.is_rx  # an adapter's echo of a frame this side sent
        ):
            return
        now = self._clock()
        with self._lock:
            self._frames += 1
            self._previous, self._last = self._last, now

    def seen(self) -> HeardSync:
        now = self._clock()
        with self._lock:
            frames, last, previous = self._frames, self._last, self._previous
        age = None if last is None else max(now - last, 0.0)
        period = None if last is None or previous is None else round((last - previous) * US)
        return HeardSync(frames=frames, age_s=age, period_us=period)
