"""Bus statistics: frames received and sent, error frames, bus failures, reconnects.

How each number is counted (so the figures in the UI can be trusted):
- rx_frames / error_frames: a `can.Listener` on the notifier counts every message python-can
  hands over; error frames are the ones flagged `is_error_frame` (only interfaces that report
  them, e.g. socketcan with error frames enabled, produce any).
- tx_frames: the `MonitoredBus` wrapper counts every `send` that python-can accepted. canopen
  sends through `Network.send_message` -> `bus.send`, and periodic messages (our SYNC producer)
  run python-can's thread-based cyclic task, which calls the same `send`: all are counted.
- bus_errors: every exception the adapter raised on receive or send.
- reconnects: each time the same configuration was connected again (automatically after a
  failure, or by `reconnect()`).
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass

import can


@dataclass(frozen=True)
class CounterSnapshot:
    rx_frames: int
    tx_frames: int
    error_frames: int
    bus_errors: int
    reconnects: int


class BusCounters:
    """Counters shared by the notifier thread, the threads that send, and the event loop."""

    def __init__(self) -> None:
        # `+=` on an attribute is not atomic across threads; node workers send concurrently.
        self._lock = threading.Lock()
        self._rx = 0
        self._tx = 0
        self._error_frames = 0
        self._bus_errors = 0
        self._reconnects = 0

    def received(self, *, error_frame: bool) -> None:
        with self._lock:
            self._rx += 1
            if error_frame:
                self._error_frames += 1

    def sent(self) -> None:
        with self._lock:
            self._tx += 1

    def bus_error(self) -> None:
        with self._lock:
            self._bus_errors += 1

    def reconnected(self) -> None:
        with self._lock:
            self._reconnects += 1

    def snapshot(self) -> CounterSnapshot:
        with self._lock:
            return CounterSnapshot(
                rx_frames=self._rx,
                tx_frames=self._tx,
                error_frames=self._error_frames,
                bus_errors=self._bus_errors,
                reconnects=self._reconnects,
            )


class CountingListener(can.Listener):
    """Counts received frames; a receive error is handed to `on_error` (which must not block).

    Handling the error here keeps the notifier thread alive: the `MonitoredBus` stays quiet
    after its first failure, and the connection manager replaces the whole link.
    """

    def __init__(self, counters: BusCounters, on_error: Callable[[Exception], None]) -> None:
        self._counters = counters
        self._on_error = on_error

    def on_message_received(self, msg: can.Message) -> None:
        self._counters.received(error_frame=msg.is_error_frame)

    def on_error(self, exc: Exception) -> None:
        self._on_error(exc)

    def stop(self) -> None:
        """Nothing to release: the counters outlive the notifier."""
