"""Live capture of PDO frames: which COB-IDs are seen, how often, and their last data.

canopen calls the subscribed callbacks on python-can's notifier thread, so a callback only
records (a counter, a timestamp, the data) under a small lock: no I/O, no decoding there
(DESIGN rule 1). Decoding is the reader's business (pdo/decode.py), so other captures (the
scope) can reuse the same decoder with their own buffers.
"""

from __future__ import annotations

import contextlib
import threading
import time
from collections import deque
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import canopen

RATE_WINDOW_S = 2.0  # the measured rate counts frames over this sliding window
MAX_TIMES = 4096  # timestamps kept per COB-ID: 2 s at 2 kHz

Clock = Callable[[], float]


@dataclass(frozen=True, slots=True)
class FrameStats:
    """One COB-ID as seen so far."""

    frames: int
    # (n - 1) / (last - first) over the n frames of the last RATE_WINDOW_S; None below 2 frames
    rate_hz: float | None
    last_data: bytes | None
    age_s: float | None  # since the last frame
    # (frames - 1) / (last - first) since the capture started: a slow PDO's rate too
    mean_hz: float | None = None


class _Buffer:
    """Written on the notifier thread, read on the event loop."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._times: deque[float] = deque(maxlen=MAX_TIMES)
        self._frames = 0
        self._last: bytes | None = None
        self._last_time: float | None = None
        self._first_time: float | None = None

    def record(self, data: bytes, now: float) -> None:
        with self._lock:
            self._frames += 1
            self._times.append(now)
            self._last = data
            self._last_time = now
            if self._first_time is None:
                self._first_time = now

    def stats(self, now: float) -> FrameStats:
        with self._lock:
            while self._times and self._times[0] < now - RATE_WINDOW_S:
                self._times.popleft()
            recent = len(self._times)
            span = self._times[-1] - self._times[0] if recent else 0.0
            frames, data, last_time = self._frames, self._last, self._last_time
            first_time = self._first_time
        # frame to frame: a single frame (or two at once) has no rate yet
        rate = (recent - 1) / span if recent >= 2 and span > 0 else None
        age = None if last_time is None else max(now - last_time, 0.0)
        whole = None if first_time is None or last_time is None else last_time - first_time
        mean = (frames - 1) / whole if frames >= 2 and whole else None
        return FrameStats(frames=frames, rate_hz=rate, last_data=data, age_s=age, mean_hz=mean)


class PdoCapture:
    """Subscriptions to a set of COB-IDs on one canopen Network."""

    def __init__(
        self, network: canopen.Network, cob_ids: Mapping[int, object], clock: Clock = time.monotonic
    ) -> None:
        self.network = network
        self._clock = clock
        self.started_wall = time.time()
        self._buffers = {cob: _Buffer() for cob in cob_ids}
        self._callbacks: dict[int, Callable[[int, bytearray, float], None]] = {}
        self._active = False

    @property
    def cob_ids(self) -> list[int]:
        return sorted(self._buffers)

    def start(self) -> None:
        for cob, buffer in self._buffers.items():
            callback = self._recorder(buffer)
            self._callbacks[cob] = callback
            self.network.subscribe(cob, callback)
        self._active = True

    def stop(self) -> None:
        if not self._active:
            return
        self._active = False
        for cob, callback in self._callbacks.items():
            with contextlib.suppress(ValueError):  # the network already forgot it
                self.network.unsubscribe(cob, callback)
        self._callbacks.clear()

    def stats(self, cob: int) -> FrameStats:
        return self._buffers[cob].stats(self._clock())

    def _recorder(self, buffer: _Buffer) -> Callable[[int, bytearray, float], None]:
        clock = self._clock

        def on_frame(_can_id: int, data: bytearray, _timestamp: float) -> None:
            buffer.record(bytes(data), clock())  # notifier thread: record only

        return on_frame
