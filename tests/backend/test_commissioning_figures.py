"""The stop and move figures from synthetic sample arrays (pure: no bus, no clock)."""

from __future__ import annotations

import numpy as np
import pytest

from servodesk.commissioning import move_figures as mf
from servodesk.commissioning import stop_figures as sf

DT = 0.002  # a 2 ms SYNC


def ramp_down(
    v0: float, decel: float, *, lead: float = 0.1, delay: float = 0.0, tail: float = 0.2
) -> tuple[sf.Series, sf.Series]:
    """Samples of a stop sent at t = lead: at v0 rpm for `delay`, then down at `decel` rpm/s,
    then at rest; positions integrated (rev)."""
    t = np.arange(0.0, lead + delay + abs(v0) / decel + tail, DT)
    after = np.clip(t - lead - delay, 0.0, None)
    v = np.sign(v0) * np.clip(abs(v0) - decel * after, 0.0, None)
    p = np.concatenate([[0.0], np.cumsum((v[1:] + v[:-1]) / 2 * DT / 60)])
    return sf.Series.of(t, v), sf.Series.of(t, p)


@pytest.mark.parametrize(
    ("v0", "decel", "delay"),
    [(300.0, 3000.0, 0.0), (-300.0, 3000.0, 0.0), (1000.0, 20000.0, 0.0), (300.0, 3000.0, 0.2)],
)
def test_a_stop_on_its_ramp_matches_the_prediction(v0: float, decel: float, delay: float) -> None:
    velocity, position = ramp_down(v0, decel, delay=delay)
    figures = sf.stop_figures(
        velocity, position, 0.1, rest_rpm=5.0, deceleration_rpm_s=decel, delay_s=delay
    )
    assert figures.speed_rpm == pytest.approx(abs(v0))
    assert figures.predicted_time_s == pytest.approx(delay + abs(v0) / decel)
    assert figures.predicted_distance_rev == pytest.approx(
        abs(v0) / 60 * delay + v0 * v0 / (120 * decel)
    )
    # rest below 5 rpm comes a little before the ramp's end; one sample's spacing either way
    assert figures.stop_time_s == pytest.approx(figures.predicted_time_s, abs=5 / decel + DT)
    assert figures.distance_rev == pytest.approx(figures.predicted_distance_rev, rel=0.02)
    assert figures.time_ratio == pytest.approx(1.0, abs=0.1)
    assert sf.verdict("quick stop", figures, 5.0) is None
    assert set(figures.figures("qs")) >= {"qs_stop_time_s", "qs_distance_rev", "qs_time_ratio"}


def test_a_slow_stop_fails_with_the_margin_named() -> None:
    velocity, position = ramp_down(300.0, 300.0)  # takes 1 s; 6085h says 0.1 s
    figures = sf.stop_figures(velocity, position, 0.1, rest_rpm=5.0, deceleration_rpm_s=3000.0)
    assert figures.stop_time_s == pytest.approx(1.0, abs=0.03)
    reason = sf.verdict("quick stop", figures, 5.0)
    assert reason is not None
    assert "longer than the 0.100 s predicted allows" in reason
    assert "0.650 s" in reason  # 1.5 × 0.1 + 0.5


def test_an_axis_still_moving_at_the_end_did_not_come_to_rest() -> None:
    t = np.arange(0.0, 1.0, DT)
    velocity = sf.Series.of(t, np.full_like(t, 100.0))
    position = sf.Series.of(t, t * 100 / 60)
    figures = sf.stop_figures(velocity, position, 0.1, rest_rpm=5.0, deceleration_rpm_s=1000.0)
    assert figures.rest_at is None
    assert figures.stop_time_s is None
    assert figures.distance_rev is None
    assert figures.time_ratio is None
    assert "did not come to rest" in (sf.verdict("quick stop", figures, 5.0) or "")


def test_a_blip_below_the_threshold_is_not_rest() -> None:
    """Rest is the last entry below the threshold for good, not a dip on the way."""
    t = np.arange(0.0, 0.5, 0.01)
    v = np.where(t < 0.3, 100.0, 0.0)
    v[5] = 0.0  # one sample of 0 while still moving
    rest = sf.rest_time(sf.Series.of(t, v), 0.0, 5.0)
    assert rest == pytest.approx(0.3)


@pytest.mark.parametrize(
    ("speed", "decel", "expected"),
    [(300.0, None, (None, None)), (300.0, 0.0, (None, None)), (0.0, 1000.0, (0.0, 0.0))],
)
def test_no_prediction_without_a_deceleration(
    speed: float, decel: float | None, expected: tuple[float | None, float | None]
) -> None:
    assert sf.predict(speed, decel) == expected


def move(
    distance: float, *, overshoot: float = 0.0, lead: float = 0.05, duration: float = 0.5
) -> sf.Series:
    """A move sent at t = lead: a smooth S to `distance`, with an overshoot bump that decays."""
    t = np.arange(0.0, lead + duration + 0.5, DT)
    s = np.clip((t - lead) / duration, 0.0, 1.0)
    p = distance * (3 * s**2 - 2 * s**3)
    after = np.clip(t - lead - duration, 0.0, None)
    p = p + np.sign(distance) * overshoot * np.sin(np.pi * np.clip(after / 0.1, 0, 1))
    return sf.Series.of(t, p)


@pytest.mark.parametrize("distance", [1.0, -0.5])
def test_a_clean_move_reaches_its_target_without_overshoot(distance: float) -> None:
    position = move(distance)
    figures = mf.move_figures(position, 0.05, 0.0, distance, 0.001)
    assert figures.distance_rev == distance
    assert 0.4 < (figures.time_to_target_s or 0) <= 0.5 + DT
    assert figures.settling_time_s == pytest.approx(figures.time_to_target_s)
    assert figures.overshoot_rev == pytest.approx(0.0, abs=1e-9)
    assert figures.overshoot_pct == pytest.approx(0.0, abs=1e-6)
    assert figures.peak_following_error_rev is None


def test_overshoot_and_settling_after_it() -> None:
    position = move(1.0, overshoot=0.02)
    velocity = sf.Series.of(position.times, np.gradient(position.values, DT) * 60)
    error = sf.Series.of(position.times, np.where(position.times > 0.3, -0.004, 0.001))
    words = sf.Series.of(position.times, np.where(position.times < 0.06, 0x1437, 0x1037))
    words.values[position.times >= 0.7] = 0x1437  # bit 10 again once settled
    figures = mf.move_figures(
        position, 0.05, 0.0, 1.0, 0.001, velocity=velocity, following_error=error, statusword=words
    )
    assert figures.overshoot_rev == pytest.approx(0.02, rel=0.01)
    assert figures.overshoot_pct == pytest.approx(2.0, rel=0.01)
    # first in the window at the end of the S, out on the bump, back in once it decays
    assert figures.time_to_target_s is not None
    assert figures.settling_time_s is not None
    assert figures.time_to_target_s < 0.5 < figures.settling_time_s < 0.6 + DT
    assert figures.peak_following_error_rev == pytest.approx(0.004)
    assert figures.target_reached_bit_s == pytest.approx(0.65, abs=DT)
    assert figures.peak_velocity_rpm == pytest.approx(1.5 / 0.5 * 60, rel=0.02)


def test_a_move_that_ends_outside_the_window_has_no_settling_time() -> None:
    position = move(1.0)
    position.values[-1] = 0.9
    figures = mf.move_figures(position, 0.05, 0.0, 1.0, 0.001)
    assert figures.time_to_target_s is not None
    assert figures.settling_time_s is None
    slow = move(1.0, duration=5.0)
    cut = slow.times < 2.0  # the capture ended with the move half way
    short = mf.move_figures(sf.Series(slow.times[cut], slow.values[cut]), 0.05, 0.0, 1.0, 0.001)
    assert short.time_to_target_s is None
    assert short.settling_time_s is None
    assert "time_to_target_s" not in short.figures()
