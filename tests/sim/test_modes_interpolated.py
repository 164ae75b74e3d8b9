"""Interpolated position: points on SYNC, linear spreading over 60C2h, one period of planning
ahead (MDi-S1-C manual figure 3.6), the 1–20 ms clamp, bit 4 / bit 12, and SYNC loss."""

from __future__ import annotations

import pytest

from servodesk_sim.fault_kind import FaultKind
from servodesk_sim.modes.interpolated import interpolation_period
from servodesk_sim.values import DictValues
from tests.sim.motion_rig import CIA402_CONFIG, Rig

IP_ACTIVE = 0x1000


def ip_rig(period_ms: int = 2) -> Rig:
    rig = Rig(overrides={(0x60C2, 1): period_ms})
    rig.enable(7)
    rig.controlword(0x1F)  # bit 4: enable interpolation
    return rig


def sync_point(rig: Rig, point: int) -> None:
    rig[0x60C1, 1] = point
    rig.core.on_sync()


@pytest.mark.parametrize(
    ("value", "index", "clamp", "seconds"),
    [
        (1, -3, (1, 20), 0.001),
        (8, -3, (1, 20), 0.008),
        (50, -3, (1, 20), 0.020),  # above the range: held at 20 ms (note 5)
        (0, -3, (1, 20), 0.001),
        (25, -4, (1, 20), 0.0025),  # 25 x 0.1 ms
        (2, -2, (1, 50), 0.020),  # 2 x 10 ms with a wider clamp
    ],
)
def test_interpolation_period(
    value: int, index: int, clamp: tuple[int, int], seconds: float
) -> None:
    values = DictValues({(0x60C2, 1): value, (0x60C2, 2): index})
    assert interpolation_period(values, clamp) == pytest.approx(seconds)


def test_bit_4_enables_interpolation_and_bit_12_shows_it() -> None:
    rig = Rig()
    rig.enable(7)
    assert not rig.statusword & IP_ACTIVE
    rig.controlword(0x1F)
    assert rig.statusword & IP_ACTIVE
    rig.controlword(0x0F)
    assert not rig.statusword & IP_ACTIVE


def test_points_are_travelled_one_period_later_spread_linearly() -> None:
    rig = ip_rig(period_ms=2)
    sync_point(rig, 1000)  # P1: planned, no motion yet (figure 3.6 note 1)
    rig.step(2)
    assert rig[0x6064] == 0
    sync_point(rig, 3000)  # P2 arrives; the axis now runs P0 -> P1 (note 2)
    demands = []
    for _ in range(2):
        rig.step()
        demands.append(rig[0x6064] + rig[0x60F4])  # position demand = actual + error
    assert demands == [500, 1000]  # the increment spread evenly over the 2 ms period
    sync_point(rig, 3000)
    rig.step(2)
    assert rig[0x6064] + rig[0x60F4] == 3000  # P1 -> P2 (note 3)


def test_a_stream_of_points_is_followed_closely() -> None:
    rig = ip_rig(period_ms=2)
    step = 200  # units per 2 ms period: 1e5 units/s = 60 rpm
    errors = []
    for n in range(1, 301):
        sync_point(rig, n * step)
        rig.step(2)
        errors.append(abs(rig[0x60F4]))
    assert rig[0x606C] == 60
    assert rig[0x6064] == pytest.approx(299 * step, abs=20)
    assert max(errors) < 60  # the start: a linear segment is a velocity step
    assert max(errors[30:]) < 5  # settled after ~60 ms (position loop time constant)
    assert rig.faults == []


def test_sync_loss_after_three_periods_faults_once() -> None:
    rig = ip_rig(period_ms=2)
    for n in range(5):
        sync_point(rig, n * 10)
        rig.step(2)
    rig.step(4)  # 6 ms = three periods since the last SYNC: still fine
    assert rig.faults == []
    rig.step(1)
    assert rig.faults == [FaultKind.SYNC_LOST]
    rig.step(20)
    assert rig.faults == [FaultKind.SYNC_LOST]


def test_no_sync_watch_while_interpolation_is_off() -> None:
    rig = Rig(CIA402_CONFIG)
    rig.enable(7)
    rig.run(0.1)
    assert rig.faults == []


def test_sync_is_ignored_outside_interpolation() -> None:
    rig = Rig()
    rig.enable(1)
    sync_point(rig, 5000)
    sync_point(rig, 5000)
    rig.run(0.1)
    assert rig[0x6064] == 0


def test_disabling_interpolation_holds_the_position() -> None:
    rig = ip_rig(period_ms=1)
    for n in range(1, 50):
        sync_point(rig, n * 100)
        rig.step()
    rig.controlword(0x0F)
    held = rig[0x6064] + rig[0x60F4]
    sync_point(rig, 999999)
    rig.run(0.2)
    assert rig[0x6064] == held
    assert rig.faults == []
