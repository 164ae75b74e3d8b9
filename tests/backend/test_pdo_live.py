"""The live capture's frame rate (pdo/live.py) with a hand-driven clock: no rate from a single
frame, then frame to frame over the sliding window."""

from __future__ import annotations

from collections.abc import Callable

import pytest

from servodesk.pdo.live import RATE_WINDOW_S, PdoCapture

COB = 0x181
Callback = Callable[[int, bytearray, float], None]


class FakeNetwork:
    """What PdoCapture uses of a canopen Network: subscribe and unsubscribe."""

    def __init__(self) -> None:
        self.callbacks: dict[int, Callback] = {}

    def subscribe(self, can_id: int, callback: Callback) -> None:
        self.callbacks[can_id] = callback

    def unsubscribe(self, can_id: int, callback: Callback) -> None:
        del self.callbacks[can_id]


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def capture() -> tuple[PdoCapture, Clock, Callable[[float], None]]:
    network, clock = FakeNetwork(), Clock()
    live = PdoCapture(network, {COB: None}, clock=clock)  # type: ignore[arg-type]
    live.start()

    def frame_at(t: float) -> None:
        clock.now = t
        network.callbacks[COB](COB, bytearray(b"\x50\x02"), t)

    return live, clock, frame_at


def test_no_rate_before_two_frames() -> None:
    live, clock, frame_at = capture()
    assert live.stats(COB).rate_hz is None
    frame_at(100.02)  # a single frame 20 ms after the start is no "51 frames/s"
    clock.now = 100.05
    stats = live.stats(COB)
    assert (stats.frames, stats.rate_hz) == (1, None)
    assert stats.last_data == b"\x50\x02"


def test_rate_from_frame_to_frame_in_the_window() -> None:
    live, clock, frame_at = capture()
    for n in range(6):  # every 100 ms: 5 intervals over 0.5 s
        frame_at(100.0 + 0.1 * n)
    clock.now = 100.55
    assert live.stats(COB).rate_hz == pytest.approx(10.0)
    # frames older than the window no longer count; alone, the last one gives no rate
    clock.now = 100.5 + RATE_WINDOW_S - 0.01
    assert live.stats(COB).rate_hz is None
    assert live.stats(COB).frames == 6
