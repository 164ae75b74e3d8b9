"""Stop figures from a capture's samples (pure: table-tested): when the axis came to rest after a
stop was sent, how far it ran, and what the deceleration predicts (t = v/a, d = v²/2a).

Times are epoch seconds (the samples' `timestamp`, the moment the stop was handed to the drive's
priority lane), velocities rpm, positions rev: the scope's physical units."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

Floats = npt.NDArray[np.float64]

# A stop fails when it takes longer than predicted × MARGIN_FACTOR + MARGIN_SLACK_S. The factor
# covers a drive's ramp that is not exactly its nominal one (jerk limits, the rest threshold);
# the slack covers what the measurement includes beyond the ramp: the stop's trip through the
# node's queue and the bus, the drive's cycle, the SYNC sample spacing and, on a busy PC, the
# event loop's lag (with a steep 6085h, a few ms of ramp, these dominate).
MARGIN_FACTOR = 1.5
MARGIN_SLACK_S = 0.5


@dataclass(frozen=True, slots=True)
class Series:
    """One signal's samples in time order."""

    times: Floats
    values: Floats

    @classmethod
    def of(cls, times: list[float] | Floats, values: list[float] | Floats) -> Series:
        return cls(np.asarray(times, dtype=np.float64), np.asarray(values, dtype=np.float64))

    def __len__(self) -> int:
        return len(self.times)

    def at(self, t: float) -> float | None:
        """The value at `t`, interpolated between the samples around it; None outside them."""
        if len(self.times) == 0 or t < self.times[0] or t > self.times[-1]:
            return None
        return float(np.interp(t, self.times, self.values))

    def at_or_before(self, t: float) -> float | None:
        i = int(np.searchsorted(self.times, t, side="right")) - 1
        return None if i < 0 else float(self.values[i])


@dataclass(frozen=True, slots=True)
class StopFigures:
    speed_rpm: float  # |606Ch| when the stop was sent
    rest_at: float | None  # epoch s of the first sample at rest for good; None: never at rest
    stop_time_s: float | None  # stop sent → at rest
    distance_rev: float | None  # run from the stop being sent to rest
    predicted_time_s: float | None  # delay + v/a; None without a deceleration
    predicted_distance_rev: float | None  # v·delay + v²/2a

    @property
    def time_ratio(self) -> float | None:
        return _ratio(self.stop_time_s, self.predicted_time_s)

    @property
    def distance_ratio(self) -> float | None:
        return _ratio(self.distance_rev, self.predicted_distance_rev)

    def allowed_time_s(self) -> float | None:
        if self.predicted_time_s is None:
            return None
        return self.predicted_time_s * MARGIN_FACTOR + MARGIN_SLACK_S

    def figures(self, prefix: str) -> dict[str, float]:
        """The numbers for the step's `figures`, rounded, those that exist."""
        values = {
            "speed_rpm": self.speed_rpm,
            "stop_time_s": self.stop_time_s,
            "distance_rev": self.distance_rev,
            "predicted_time_s": self.predicted_time_s,
            "predicted_distance_rev": self.predicted_distance_rev,
            "time_ratio": self.time_ratio,
            "distance_ratio": self.distance_ratio,
        }
        return {f"{prefix}_{k}": round(v, 4) for k, v in values.items() if v is not None}


def _ratio(measured: float | None, predicted: float | None) -> float | None:
    if measured is None or predicted is None or predicted <= 0:
        return None
    return measured / predicted


def rest_time(velocity: Series, after: float, rest_rpm: float) -> float | None:
    """The first sample at or after `after` from which |v| stays below `rest_rpm` to the end of
    the capture; None when the last sample still moves (or there is none after `after`)."""
    times, values = velocity.times, velocity.values
    start = int(np.searchsorted(times, after, side="left"))
    if start >= len(times):
        return None
    moving = np.nonzero(np.abs(values[start:]) >= rest_rpm)[0]
    if len(moving) == 0:
        return float(times[start])
    last = start + int(moving[-1])
    return None if last + 1 >= len(times) else float(times[last + 1])


def predict(speed_rpm: float, deceleration_rpm_s: float | None, delay_s: float = 0.0) -> tuple[
    float | None, float | None
]:  # fmt: skip
    """(time s, distance rev) to stop from `speed_rpm` on `deceleration_rpm_s`, running on at
    speed for `delay_s` first (a keep-alive window): t = delay + v/a, d = v·delay + v²/2a."""
    if deceleration_rpm_s is None or deceleration_rpm_s <= 0 or not math.isfinite(speed_rpm):
        return None, None
    v = abs(speed_rpm)
    ramp = v / deceleration_rpm_s
    # rpm → rev/s is /60, rpm/s → rev/s² is /60: v²/2a = (v/60)² / (2·a/60) = v² / (120·a)
    return delay_s + ramp, v / 60 * delay_s + v * v / (120 * deceleration_rpm_s)


def stop_figures(
    velocity: Series,
    position: Series,
    stop_at: float,
    *,
    rest_rpm: float,
    deceleration_rpm_s: float | None,
    delay_s: float = 0.0,
) -> StopFigures:
    """The stop sent at `stop_at` (epoch s) as the capture saw it, against the prediction from
    `deceleration_rpm_s` (the drive's 6085h in rpm/s) after `delay_s` at speed."""
    speed = abs(velocity.at_or_before(stop_at) or 0.0)
    rest_at = rest_time(velocity, stop_at, rest_rpm)
    stop_time = distance = None
    if rest_at is not None:
        stop_time = max(0.0, rest_at - stop_at)
        start = position.at(stop_at)
        if start is None:
            start = position.at_or_before(stop_at)
        end = position.at(rest_at)
        if start is not None and end is not None:
            distance = abs(end - start)
    predicted_time, predicted_distance = predict(speed, deceleration_rpm_s, delay_s)
    return StopFigures(speed, rest_at, stop_time, distance, predicted_time, predicted_distance)


def verdict(name: str, figures: StopFigures, rest_rpm: float) -> str | None:
    """Why the stop fails (one line), or None: it did not come to rest, or took longer than the
    prediction allows (MARGIN_FACTOR × predicted + MARGIN_SLACK_S)."""
    if figures.stop_time_s is None:
        return f"{name}: the axis did not come to rest (|606Ch| < {rest_rpm:g} rpm) in the capture"
    allowed = figures.allowed_time_s()
    if allowed is not None and figures.stop_time_s > allowed:
        return (
            f"{name}: stopped in {figures.stop_time_s:.3f} s, longer than the "
            f"{figures.predicted_time_s:.3f} s predicted allows ({MARGIN_FACTOR:g} × + "
            f"{MARGIN_SLACK_S:g} s = {allowed:.3f} s)"
        )
    return None
