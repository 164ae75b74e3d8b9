"""Test-move figures from a capture's samples (pure: table-tested): time to target, overshoot,
settling time and peak following error of a PP move.

Times are epoch seconds (the samples' `timestamp`; `start_at` is when the set-point was sent),
positions and following error rev (the scope's physical units), `window` the drive's position
window 6067h in rev."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from servodesk.commissioning.stop_figures import Series

TARGET_REACHED_BIT = 10  # 6041h bit 10: target reached


@dataclass(frozen=True, slots=True)
class MoveFigures:
    distance_rev: float  # target − start (signed)
    time_to_target_s: float | None  # first entry into the window around the target
    target_reached_bit_s: float | None  # 6041h bit 10 set again after the move began
    overshoot_rev: float  # past the target, in the direction of the move (≥ 0)
    overshoot_pct: float | None  # of the distance
    settling_time_s: float | None  # last entry into the window (None: it left it at the end)
    peak_following_error_rev: float | None  # max |60F4h| during the move
    peak_velocity_rpm: float | None

    def figures(self) -> dict[str, float]:
        values = {
            "move_distance_rev": self.distance_rev,
            "time_to_target_s": self.time_to_target_s,
            "target_reached_bit_s": self.target_reached_bit_s,
            "overshoot_rev": self.overshoot_rev,
            "overshoot_pct": self.overshoot_pct,
            "settling_time_s": self.settling_time_s,
            "peak_following_error_rev": self.peak_following_error_rev,
            "peak_velocity_rpm": self.peak_velocity_rpm,
        }
        return {k: round(v, 6) for k, v in values.items() if v is not None}


def _from(series: Series, start_at: float) -> Series:
    i = int(np.searchsorted(series.times, start_at, side="left"))
    return Series(series.times[i:], series.values[i:])


def _bit_set_again(statusword: Series, start_at: float) -> float | None:
    """When bit 10 was set after having been cleared by the new set-point (a bit still set from
    the last move is not this one's)."""
    words = _from(statusword, start_at)
    bits = (words.values.astype(np.int64) >> TARGET_REACHED_BIT) & 1
    cleared = np.nonzero(bits == 0)[0]
    if len(cleared) == 0:
        return None
    again = np.nonzero(bits[cleared[0] :] == 1)[0]
    return None if len(again) == 0 else float(words.times[cleared[0] + again[0]])


def move_figures(
    position: Series,
    start_at: float,
    start_rev: float,
    target_rev: float,
    window_rev: float,
    *,
    velocity: Series | None = None,
    following_error: Series | None = None,
    statusword: Series | None = None,
) -> MoveFigures:
    moved = _from(position, start_at)
    distance = target_rev - start_rev
    direction = 1.0 if distance >= 0 else -1.0
    inside = np.abs(moved.values - target_rev) <= window_rev
    time_to_target = settling = None
    if inside.any():
        time_to_target = float(moved.times[int(np.argmax(inside))]) - start_at
        outside = np.nonzero(~inside)[0]
        if len(outside) == 0:
            settling = float(moved.times[0]) - start_at
        elif outside[-1] + 1 < len(inside):
            settling = float(moved.times[outside[-1] + 1]) - start_at
    beyond = (moved.values - target_rev) * direction
    overshoot = max(0.0, float(beyond.max())) if len(beyond) else 0.0
    percent = overshoot / abs(distance) * 100 if distance else None
    peak_error = None
    if following_error is not None:
        errors = _from(following_error, start_at).values
        peak_error = float(np.abs(errors).max()) if len(errors) else None
    peak_velocity = None
    if velocity is not None:
        speeds = _from(velocity, start_at).values
        peak_velocity = float(np.abs(speeds).max()) if len(speeds) else None
    bit = _bit_set_again(statusword, start_at) if statusword is not None else None
    return MoveFigures(
        distance_rev=distance,
        time_to_target_s=time_to_target,
        target_reached_bit_s=None if bit is None else bit - start_at,
        overshoot_rev=overshoot,
        overshoot_pct=percent,
        settling_time_s=settling,
        peak_following_error_rev=peak_error,
        peak_velocity_rpm=peak_velocity,
    )
