"""Can this host keep an IP stream's SYNC on time? Checked before anything is sent.

The stream sends each SYNC from the node's worker thread at its absolute deadline (motion/ip.py),
and the drive faults with SYNC lost after 3 periods without one. Before the stream, the same
thread sleeps to PROBE_S worth of those deadlines without sending; the worst lateness it sees is
what the stream would see. A gap of more than 2 periods leaves less than one period to the
drive's fault: the stream is refused (409 sync_unsafe). A jitter beyond half a period is said in
the result's message; the stream runs.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

from servodesk.errors import ServodeskError
from servodesk.motion.trajectory import sync_jitter

PROBE_S = 0.2  # long enough to see a scheduler stall, short beside a stream
PROBE_MIN_PERIODS = 20
REFUSE_PERIODS = 2.0  # longest interval beyond this many periods: refuse
WARN_PERIODS = 0.5  # jitter beyond this many periods: say so
LOST_AFTER_PERIODS = 3  # the drives' SYNC-lost alarm (MDi 62, Kinco 6011h, CiA 402 8700h)


@dataclass(frozen=True)
class SyncTiming:
    """What the probe measured, in seconds."""

    period: float
    periods: int  # intervals measured
    jitter: float  # worst |interval − period|
    longest: float  # longest interval

    @property
    def unsafe(self) -> bool:
        return self.longest > REFUSE_PERIODS * self.period

    @property
    def marginal(self) -> bool:
        return self.jitter > WARN_PERIODS * self.period

    def words(self) -> str:
        return (
            f"SYNC jitter {self.jitter * 1000:.2f} ms, longest interval "
            f"{self.longest * 1000:.2f} ms over {self.periods} "
            f"period{'' if self.periods == 1 else 's'} of {self.period * 1000:g} ms"
        )


class SyncUnsafeError(ServodeskError):
    """The host cannot keep the stream's SYNC within a period of its deadlines right now."""

    def __init__(self, node: int, timing: SyncTiming) -> None:
        self.node = node
        self.timing = timing
        lost_ms = LOST_AFTER_PERIODS * timing.period * 1000
        super().__init__(
            f"node {node}: SYNC timing on this computer is unsafe for a "
            f"{timing.period * 1000:g} ms stream ({timing.words()}; the drive faults after "
            f"{lost_ms:g} ms without SYNC); nothing was sent: choose a longer period or reduce "
            "the load on this computer, then try again"
        )


def probe_periods(period: float) -> int:
    return max(PROBE_MIN_PERIODS, math.ceil(PROBE_S / period))


def sleep_until(deadline: float) -> float:
    """Sleep in short naps (each gives the interpreter lock to the other threads) until
    `deadline` (perf_counter); returns the time it woke."""
    while (left := deadline - time.perf_counter()) > 0:
        time.sleep(left - 0.001 if left > 0.002 else min(left, 0.0002))
    return time.perf_counter()


@dataclass
class SyncClock:
    """A stream's SYNC deadlines, one period apart from `start`. A SYNC sent more than half a
    period late moves every later deadline by its lateness: the path is delayed, never
    compressed into a burst of SYNCs that would drive the axis faster than planned (and that
    python-can's cyclic task would send after a stall)."""

    start: float
    period: float

    def wait(self, k: int) -> float:
        """Sleep until SYNC `k` is due; the time it woke."""
        deadline = self.start + k * self.period
        now = sleep_until(deadline)
        if now - deadline > self.period / 2:
            self.start += now - deadline
        return now


def probe(period: float) -> SyncTiming:
    """Sleep to `probe_periods(period)` absolute deadlines one period apart, as the stream's SYNC
    loop does, and measure when this thread woke. Blocking: run it on the node's worker
    thread, where the stream will run."""
    count = probe_periods(period)
    start = time.perf_counter() + period
    stamps: list[float] = []
    for k in range(count):
        stamps.append(sleep_until(start + k * period))
        if k and stamps[-1] - stamps[-2] > REFUSE_PERIODS * period:
            break  # unsafe already: a loaded host need not wait for the rest
    jitter, longest = sync_jitter(stamps, period)
    return SyncTiming(period, len(stamps) - 1, jitter, longest)
