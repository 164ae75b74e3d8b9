"""The arithmetic every mode shares: velocity ramps, the on-line trapezoid, the stop ramp,
the "per ms" acceleration unit and the simulated switches."""

from __future__ import annotations

import pytest

from servodesk_sim.modes.common import (
    StopRamp,
    Switches,
    acceleration,
    ramp_velocity,
    read_switches,
    trapezoid_step,
)
from servodesk_sim.values import DictValues

DT = 0.001


@pytest.mark.parametrize(
    ("velocity", "target", "expected"),
    [
        (0.0, 100.0, 10.0),  # speeding up: acc
        (0.0, -100.0, -10.0),
        (50.0, 100.0, 60.0),
        (95.0, 100.0, 100.0),  # does not pass the target
        (100.0, 0.0, 80.0),  # slowing down: dec
        (-100.0, 0.0, -80.0),
        (10.0, -100.0, 0.0),  # through zero: stops at zero for this period
        (-10.0, 100.0, 0.0),
        (30.0, -100.0, 10.0),
        (100.0, 100.0, 100.0),
    ],
)
def test_ramp_velocity(velocity: float, target: float, expected: float) -> None:
    assert ramp_velocity(velocity, target, 10_000.0, 20_000.0, DT) == pytest.approx(expected)


def run_profile(
    target: float, vmax: float, acc: float, dec: float, velocity: float = 0.0
) -> tuple[list[float], list[float]]:
    position = 0.0
    positions, velocities = [], []
    for _ in range(100_000):
        position, velocity, arrived = trapezoid_step(position, velocity, target, vmax, acc, dec, DT)
        positions.append(position)
        velocities.append(velocity)
        if arrived:
            return positions, velocities
    raise AssertionError("profile never arrived")


@pytest.mark.parametrize(
    ("target", "vmax", "acc", "dec", "steps"),
    [
        (100_000.0, 100_000.0, 1e8, 1e8, 1001),  # the factory values: 1 ms ramps, 1 s cruise
        (200_000.0, 100_000.0, 1e5, 1e5, 3000),  # 1 s up, 1 s cruise, 1 s down
        (1_000_000.0, 1e6, 1e5, 1e5, 6325),  # triangle: 2·sqrt(d/a)
        (-50.0, 1e6, 1e5, 3e5, 37),
        (12_345.6, 5e5, 2e6, 1e6, 193),
    ],
)
def test_trapezoid_lands_on_the_target_without_overshoot(
    target: float, vmax: float, acc: float, dec: float, steps: int
) -> None:
    positions, velocities = run_profile(target, vmax, acc, dec)
    assert positions[-1] == target
    assert velocities[-1] == 0.0
    assert len(positions) == pytest.approx(steps, abs=2)
    assert max(abs(v) for v in velocities) <= vmax
    assert max(p * (1 if target > 0 else -1) for p in positions) <= abs(target)


def test_trapezoid_turns_back_when_moving_away() -> None:
    positions, _ = run_profile(-1000.0, 1e5, 1e6, 1e6, velocity=50_000.0)
    assert max(positions) == pytest.approx(50_000.0**2 / 2e6, rel=0.01)  # braked at dec
    assert positions[-1] == -1000.0


def test_stop_ramp_brakes_to_standstill() -> None:
    ramp = StopRamp()
    ramp.start(10.0, 1000.0)
    steps = 0
    while not ramp.stopped:
        setpoint = ramp.step(DT, 100_000.0)
        steps += 1
    assert steps == 10
    assert setpoint.position == pytest.approx(10.0 + 1000.0**2 / 2e5)
    assert setpoint.velocity == 0.0


@pytest.mark.parametrize(("raw", "expected"), [(0, 1000.0), (1, 1000.0), (100_000, 1e8)])
def test_acceleration_is_units_per_second_per_millisecond(raw: int, expected: float) -> None:
    assert acceleration(raw) == expected


LAYOUT = DictValues({(0x5FF1, 0): -1000, (0x5FF2, 0): 1000, (0x5FF3, 0): 100, (0x5FF4, 0): 200})


@pytest.mark.parametrize(
    ("position", "expected"),
    [
        (0.0, Switches(0)),
        (-1000.0, Switches.NEGATIVE_LIMIT),  # active at and beyond the position
        (-999.5, Switches(0)),
        (1000.0, Switches.POSITIVE_LIMIT),
        (5000.0, Switches.POSITIVE_LIMIT),
        (100.0, Switches.HOME),
        (200.0, Switches.HOME),
        (200.5, Switches(0)),
    ],
)
def test_switches_from_the_simulated_positions(position: float, expected: Switches) -> None:
    assert read_switches(LAYOUT, position) == expected


def test_absent_switch_objects_are_never_active() -> None:
    assert read_switches(DictValues(), -(2.0**40)) == Switches(0)
    assert read_switches(DictValues(), 0.0) == Switches(0)
