"""Profile velocity: 60FFh over the 6083h ramp both ways, halt, target reached, over-limit."""

from __future__ import annotations

import pytest

from tests.sim.motion_rig import REV, Rig

REACHED = 0x0400
OVER_LIMIT = 0x2000


def pv_rig(overrides: dict[tuple[int, int], int] | None = None) -> Rig:
    rig = Rig(overrides={(0x6083, 0): 1000, **(overrides or {})})  # 1e6 units/s²
    rig.enable(3)
    return rig


def test_ramps_to_the_target_velocity_with_6083() -> None:
    rig = pv_rig()
    rig[0x60FF] = 6 * REV  # 360 rpm, 1e6 units/s²: 0.6 s
    rig.run(0.3)
    assert rig[0x606C] == pytest.approx(180, abs=1)
    assert not rig.statusword & REACHED
    rig.run(0.31)
    assert rig[0x606C] == 360
    assert rig.statusword & REACHED


def test_slows_down_with_6083_not_6084() -> None:
    rig = pv_rig({(0x6084, 0): 1})  # a 6084h ramp would take minutes
    rig[0x60FF] = 6 * REV
    rig.run(0.7)
    rig[0x60FF] = 0
    rig.run(0.3)
    assert rig[0x606C] == pytest.approx(180, abs=1)
    rig.run(0.31)
    assert rig[0x606C] == 0


def test_reverses_through_zero() -> None:
    rig = pv_rig()
    rig[0x60FF] = 3 * REV
    rig.run(0.4)
    rig[0x60FF] = -3 * REV
    rig.run(0.61)
    assert rig[0x606C] == -180
    assert rig.statusword & REACHED


def test_halt_brings_the_axis_to_rest_and_release_resumes() -> None:
    rig = pv_rig()
    rig[0x60FF] = 3 * REV
    rig.run(0.4)
    rig.controlword(0x10F)
    rig.run(0.31)
    assert rig[0x606C] == 0
    assert rig.statusword & REACHED
    rig.controlword(0x0F)
    rig.run(0.31)
    assert rig[0x606C] == 180


def test_bit_13_shows_a_target_above_the_speed_limit() -> None:
    rig = pv_rig({(0x2006, 8): 600})
    rig[0x60FF] = 6 * REV  # 360 rpm: fine
    rig.step()
    assert not rig.statusword & OVER_LIMIT
    rig[0x60FF] = -11 * REV  # 660 rpm
    rig.step()
    assert rig.statusword & OVER_LIMIT


def test_gear_ratio_sets_the_velocity_unit() -> None:
    rig = Rig(overrides={(0x6091, 2): 3600, (0x6083, 0): 1000})
    rig.enable(3)
    rig[0x60FF] = 3600  # one revolution per second in units of 0.1 degree
    rig.run(0.2)
    assert rig[0x606C] == 60
