"""Which SDO reads are polling: the same object of the same node read again and again at a
steady period, as ServoDesk's Drive page does (6041h, 6061h, 6064h, 606Ch, 6077h, 60F4h at
10 Hz) and as a PLC's status loop does. The log cannot tell which client sent a request (every
client uses 600h + node), so the rule is the traffic's shape:

an SDO read that completed is polling from the third read of one object on, while each
interval stays within half a period of the one before and the period is at most
MAX_PERIOD_S. The first two reads of a series are shown (they start it); a read off the beat
starts a new series.
"""

from __future__ import annotations

from dataclasses import dataclass

MAX_PERIOD_S = 2.0  # slower repeats are someone reading a value, not a poll loop
TOLERANCE = 0.5  # an interval may differ from the period by this share of it


@dataclass(slots=True)
class _Series:
    last: float
    period: float | None = None


class PollingDetector:
    """Feed every completed SDO read; `read(...)` says whether it is part of a poll loop."""

    def __init__(self) -> None:
        self._series: dict[tuple[int, int, int], _Series] = {}

    def read(self, time: float, node: int, index: int, subindex: int) -> bool:
        key = (node, index, subindex)
        series = self._series.get(key)
        if series is None:
            self._series[key] = _Series(time)
            return False
        interval = time - series.last
        series.last = time
        period = series.period
        steady = period is not None and 0 < period <= MAX_PERIOD_S
        if steady and period is not None and abs(interval - period) <= TOLERANCE * period:
            series.period = period + 0.2 * (interval - period)  # follows a slow drift
            return True
        series.period = interval  # the first interval of a (new) series
        return False
