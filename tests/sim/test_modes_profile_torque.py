"""Profile torque: 6071h over the 6087h slope, the speed cap at the max speed, halt."""

from __future__ import annotations

import pytest

from tests.sim.motion_rig import KINCO_CONFIG, Rig

REACHED = 0x0400


def test_torque_follows_the_slope() -> None:
    rig = Rig(overrides={(0x6087, 0): 1})  # 0.1 %/ms
    rig.enable(4)
    rig[0x6071] = 100  # 10 %
    rig.run(0.05)
    assert rig[0x6077] == pytest.approx(50, abs=1)
    assert not rig.statusword & REACHED
    rig.run(0.051)
    assert rig[0x6077] == 100
    assert rig.statusword & REACHED
    assert rig[0x606C] > 0


def test_speed_is_capped_at_the_max_speed_without_overspeed() -> None:
    rig = Rig(overrides={(0x2006, 8): 1000, (0x6087, 0): 100})
    rig.enable(4)
    rig[0x6071] = 500
    speeds = []
    for _ in range(200):  # 0.2 s: about 3 revolutions, short of P-OT
        rig.step()
        speeds.append(rig[0x606C])
    assert max(speeds) <= 1000
    assert speeds[-1] > 950  # "当速度达到限幅值将进入调速阶段"
    assert rig[0x6077] < 100  # torque falls back to what holds the speed
    assert rig.faults == []


def test_kinco_caps_at_6080() -> None:
    rig = Rig(KINCO_CONFIG, overrides={(0x6080, 0): 300, (0x6087, 0): 100})
    rig.enable(4)
    rig[0x6071] = -300
    rig.run(0.4)
    assert -300 <= rig[0x606C] < -280
    assert rig.faults == []


def test_halt_ramps_the_torque_to_zero() -> None:
    rig = Rig(overrides={(0x6087, 0): 10})
    rig.enable(4)
    rig[0x6071] = 200
    rig.run(0.05)
    rig.controlword(0x10F)
    rig.run(0.01)
    assert 0 < rig[0x6077] < 200
    rig.run(0.011)
    assert rig[0x6077] == 0
    assert rig.statusword & REACHED


def test_zero_slope_steps_the_torque() -> None:
    rig = Rig(overrides={(0x6087, 0): 0})
    rig.enable(4)
    rig[0x6071] = -150
    rig.step()
    assert rig[0x6077] == -150
