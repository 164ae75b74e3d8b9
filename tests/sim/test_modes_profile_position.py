"""Profile position: the set-point handshake of MDi-S1-C manual §3.4.2 (both timings), relative
targets, halt, target reached, and the trapezoidal profile."""

from __future__ import annotations

import pytest

from servodesk_sim.motion import MotionConfig
from tests.sim.motion_rig import CIA402_CONFIG, DT, KINCO_CONFIG, MDI_CONFIG, REV, Rig

ACK = 0x1000  # statusword bit 12, set-point acknowledge
REACHED = 0x0400  # statusword bit 10, target reached


def pp_rig(config: MotionConfig = MDI_CONFIG) -> Rig:
    rig = Rig(config, overrides={(0x6081, 0): 2 * REV})  # 2 rev/s
    rig.enable(1)
    return rig


def offer(rig: Rig, target: int, controlword: int = 0x1F) -> None:
    """Set 607Ah, raise bit 4, then drop it once bit 12 answers (the master's side)."""
    rig[0x607A] = target
    rig.controlword(controlword)
    assert rig.statusword & ACK
    rig.controlword(controlword & ~0x10)


def test_idle_axis_shows_target_reached() -> None:
    rig = pp_rig()
    assert rig.statusword & (ACK | REACHED) == REACHED


def test_mdi_handshake_bit_12_stays_until_the_move_ends() -> None:
    rig = pp_rig()
    rig[0x607A] = REV
    rig.controlword(0x1F)
    assert rig.statusword & (ACK | REACHED) == ACK  # taken at once, before any period
    rig.step(10)
    rig.controlword(0x0F)
    assert rig.statusword & ACK  # "不可更新目标位置" while the move runs
    rig.run(0.3)
    assert rig.statusword & (ACK | REACHED) == ACK
    took = rig.run_until(ACK | REACHED, REACHED)
    assert 0.1 < took < 0.4  # 1 rev at 2 rev/s: ~0.5 s in all
    assert rig[0x6064] == pytest.approx(REV, abs=100)
    rig.run(0.1)
    assert rig[0x6064] == REV


def test_mdi_ignores_a_new_set_point_while_one_runs() -> None:
    rig = pp_rig()
    offer(rig, REV)
    rig.step(50)
    rig[0x607A] = -REV
    rig.controlword(0x1F)  # bit 12 is still 1: not taken
    rig.controlword(0x0F)
    rig.run(1.0)
    assert rig[0x6064] == REV


def test_mdi_ignores_bit_5() -> None:
    rig = pp_rig()
    offer(rig, REV, 0x3F)
    assert rig.statusword & ACK  # bit 5 "立即" is not honoured: still non-immediate
    rig.step(50)
    rig[0x607A] = 0
    rig.controlword(0x3F)
    rig.controlword(0x2F)
    rig.run(1.0)
    assert rig[0x6064] == REV


@pytest.mark.parametrize("config", [CIA402_CONFIG, KINCO_CONFIG], ids=["cia402", "kinco"])
def test_immediate_set_point_replaces_the_running_one(config: MotionConfig) -> None:
    rig = pp_rig(config)
    offer(rig, 2 * REV, 0x3F)
    assert not rig.statusword & ACK  # bit 12 follows bit 4 back to 0 while moving
    rig.run(0.25)
    assert 0.3 * REV < rig[0x6064] < 0.7 * REV
    offer(rig, 0, 0x3F)
    positions = []
    for _ in range(1000):
        rig.step()
        positions.append(rig[0x6064])
    assert max(positions) < 0.8 * REV  # turned back long before 2 rev
    assert positions[-1] == 0


def test_buffered_set_point_runs_after_the_current_one() -> None:
    rig = pp_rig(CIA402_CONFIG)
    offer(rig, REV)
    assert not rig.statusword & ACK  # buffer free again
    rig.run(0.1)
    offer(rig, -REV)
    assert rig.statusword & ACK  # buffer full until the first move ends
    positions = []
    for _ in range(2000):
        rig.step()
        positions.append(rig[0x6064])
    assert max(positions) == pytest.approx(REV, abs=100)  # the first target was reached
    assert positions[-1] == -REV
    assert not rig.statusword & ACK


def test_relative_targets_add_to_the_last_target() -> None:
    rig = pp_rig(CIA402_CONFIG)
    offer(rig, REV // 2, 0x5F)
    rig.run(0.1)
    offer(rig, REV // 2, 0x5F)  # buffered, relative to the first target
    rig.run(1.5)
    assert rig[0x6064] == REV


def test_relative_target_from_standstill() -> None:
    rig = pp_rig()
    offer(rig, REV // 4)
    rig.run(0.8)
    offer(rig, -REV, 0x5F)
    rig.run(1.5)
    assert rig[0x6064] == -3 * REV // 4


def test_profile_velocity_caps_the_speed_and_6083_shapes_the_ramp() -> None:
    rig = Rig(overrides={(0x6081, 0): REV, (0x6083, 0): 100, (0x6084, 0): 100})
    rig.enable(1)
    offer(rig, 2 * REV)
    speeds = []
    for _ in range(4000):
        rig.step()
        speeds.append(rig[0x606C])
    # 1e5 units/s² reaches 1 rev/s (60 rpm) after 1 s and 0.5 rev, cruises 1 rev, brakes 1 s.
    assert max(speeds) == 60
    assert speeds[500] == pytest.approx(30, abs=1)
    assert speeds[1500] == 60
    assert speeds[2500] == pytest.approx(30, abs=1)
    assert speeds[3100] == 0
    assert rig[0x6064] == 2 * REV


def test_halt_stops_on_6084_and_resumes() -> None:
    rig = Rig(overrides={(0x6081, 0): REV, (0x6084, 0): 1000})
    rig.enable(1)
    offer(rig, 2 * REV)
    rig.run(0.5)
    rig.controlword(0x10F)  # halt
    assert not rig.statusword & REACHED
    rig.run(0.05)
    assert rig[0x606C] > 0  # 1e6 units/s²: 0.1 s to stop from 1 rev/s
    rig.run(0.1)
    assert rig[0x606C] == 0
    assert rig.statusword & REACHED  # halted at standstill
    held = rig[0x6064]
    assert held < 2 * REV
    rig.controlword(0x0F)
    assert not rig.statusword & REACHED
    rig.run(2.0)
    assert rig[0x6064] == 2 * REV


def test_target_reached_uses_the_position_window() -> None:
    rig = Rig(overrides={(0x6081, 0): REV, (0x6067, 0): 50000})
    rig.enable(1)
    offer(rig, REV)
    rig.run(0.8)
    assert not rig.statusword & REACHED  # still moving
    rig.run(0.3)
    assert rig.statusword & REACHED


def test_enabling_again_forgets_the_old_set_point() -> None:
    rig = pp_rig()
    offer(rig, 10 * REV)
    rig.run(0.2)
    rig.controlword(0x07)  # disable operation: the axis coasts
    rig.run(0.5)
    rig.controlword(0x0F)
    rig.run(0.5)
    assert rig[0x606C] == 0
    assert rig[0x6064] < 2 * REV
    assert rig.statusword & (ACK | REACHED) == REACHED


def test_following_error_object_is_small_during_a_move() -> None:
    rig = pp_rig()
    offer(rig, REV)
    worst = 0
    for _ in range(round(0.6 / DT)):
        rig.step()
        worst = max(worst, abs(rig[0x60F4]))
    assert worst < 20
