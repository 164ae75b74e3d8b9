"""Planned paths for interpolated position (IP) streams, and the statistics of a stream (pure).

Both paths start and end at rest at the start position's offset 0, so the axis is never asked
for a step in velocity: the point-to-point move follows a minimum-jerk (quintic) profile, the
"sine" is a raised cosine (one period of a sine in velocity) that goes out by `distance` and
comes back.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from typing import Literal

Trajectory = Literal["point_to_point", "sine"]


def planned_offset(trajectory: Trajectory, t: float, duration: float, distance: float) -> float:
    """Offset from the start position at time `t` (clamped to 0…duration), in the unit of
    `distance`."""
    tau = min(max(t / duration, 0.0), 1.0)
    if trajectory == "point_to_point":
        return distance * tau**3 * (10.0 - 15.0 * tau + 6.0 * tau * tau)
    return distance * 0.5 * (1.0 - math.cos(2.0 * math.pi * tau))


def peak_velocity(trajectory: Trajectory, duration: float, distance: float) -> float:
    """The path's highest speed (unit of `distance` per second): 1.875 d/T for the quintic,
    π d/T for the raised cosine."""
    factor = 1.875 if trajectory == "point_to_point" else math.pi
    return abs(distance) * factor / duration


def setpoints(
    trajectory: Trajectory, start: int, distance: float, duration: float, period: float
) -> list[int]:
    """The 60C1h:01 set-points, one per SYNC period: point k is where the axis should be at
    (k + 1) periods (a drive that interpolates one point ahead travels to it meanwhile). The
    last points hold the end position so the axis settles there."""
    count = math.ceil(duration / period)
    return [
        start + round(planned_offset(trajectory, (k + 1) * period, duration, distance))
        for k in range(count)
    ]


def sync_jitter(stamps: Sequence[float], period: float) -> tuple[float, float]:
    """(worst |interval − period|, longest interval) of SYNC send times, in seconds."""
    if len(stamps) < 2:
        return 0.0, 0.0
    intervals = [b - a for a, b in itertools.pairwise(stamps)]
    return max(abs(i - period) for i in intervals), max(intervals)
