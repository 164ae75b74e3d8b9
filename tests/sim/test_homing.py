"""Homing methods 17, 18, 23, 27, 35 as MDi-S1-C manual §3.7.3 draws them: from outside and
inside the switch, 23/27 reversing at a limit switch, errors, halt, and the statusword bits."""

from __future__ import annotations

from dataclasses import dataclass, replace

import pytest
from canopen.profiles.p402 import Homing as CanopenHoming

from servodesk_sim.fault_kind import FaultKind
from servodesk_sim.motion import MotionConfig
from tests.sim.motion_rig import INC, KINCO_CONFIG, MDI_CONFIG, Rig

ATTAINED = 0x1000
ERROR = 0x2000
REACHED = 0x0400
HOME_OFFSET = 1234
SLOW_RPM = 12  # 6099h:02 = 20000 units/s
FAST_RPM = 60  # 6099h:01 = 100000 units/s
Q = INC // 4  # a quarter revolution in encoder increments


@dataclass
class Run:
    raw: list[int]  # 6063h while homing (the encoder frame: homing has not moved it yet)
    rpm: list[int]
    inputs: list[int]  # 60FDh
    end_raw: int  # 6063h in the last period before the position was rebased

    @property
    def slowest_exit(self) -> int:
        return max(abs(r) for r in self.rpm[-5:])


def layout(
    method: int,
    *,
    n_ot: int | None = -4 * Q,
    p_ot: int | None = 4 * Q,
    home: tuple[int, int] = (16 * INC, 17 * INC),
    config: MotionConfig = MDI_CONFIG,
    **objects: int,
) -> Rig:
    overrides = {
        (0x6098, 0): method,
        (0x607C, 0): HOME_OFFSET,
        (0x5FF3, 0): home[0],
        (0x5FF4, 0): home[1],
    }
    rig = Rig(config, overrides=overrides)
    for index, value in ((0x5FF1, n_ot), (0x5FF2, p_ot)):
        if value is None:
            del rig.values.values[(index, 0)]
        else:
            rig[index] = value
    for name, value in objects.items():
        rig[int(name[1:], 16)] = value
    rig.enable(6)
    return rig


def home(rig: Rig, limit: float = 3.0) -> Run:
    rig.controlword(0x1F)
    assert rig.statusword & (ATTAINED | ERROR | REACHED) == 0  # "in progress" at once
    rig.controlword(0x0F)  # bit 4 back to 0 does not stop homing
    run = Run([], [], [], 0)
    for _ in range(round(limit / 0.001)):
        before = rig[0x6063]
        rig.step()
        if rig.statusword & (ATTAINED | ERROR):
            run.end_raw = before
            return run
        run.raw.append(rig[0x6063])
        run.rpm.append(rig[0x606C])
        run.inputs.append(rig[0x60FD])
    raise AssertionError("homing did not finish")


def assert_homed(rig: Rig) -> None:
    assert rig.statusword & (ATTAINED | ERROR | REACHED) == ATTAINED | REACHED
    assert rig[0x6064] == HOME_OFFSET  # "电机停止位置为机械原点", 607Ch
    assert rig.faults == []


def test_17_from_outside_n_ot() -> None:
    rig = layout(17, n_ot=-Q)
    run = home(rig)
    assert_homed(rig)
    assert min(run.rpm) == -FAST_RPM  # fast towards N-OT
    assert min(run.raw) < -Q  # into the switch, braked, reversed
    assert run.end_raw == pytest.approx(-Q, abs=40)  # stopped at the N-OT falling edge
    assert run.slowest_exit <= SLOW_RPM
    assert run.inputs[-1] & 0x1 == 0


def test_17_from_inside_n_ot_goes_slow_positive_only() -> None:
    rig = layout(17, n_ot=Q)
    run = home(rig)
    assert_homed(rig)
    assert min(run.raw) >= 0
    assert max(run.rpm) == SLOW_RPM
    assert run.end_raw == pytest.approx(Q, abs=40)


def test_18_from_outside_p_ot() -> None:
    rig = layout(18, p_ot=Q)
    run = home(rig)
    assert_homed(rig)
    assert max(run.rpm) == FAST_RPM
    assert max(run.raw) > Q
    assert run.end_raw == pytest.approx(Q, abs=40)


def test_18_from_inside_p_ot_goes_slow_negative_only() -> None:
    rig = layout(18, p_ot=-Q)
    run = home(rig)
    assert_homed(rig)
    assert max(run.raw) <= 0
    assert min(run.rpm) == -SLOW_RPM
    assert run.end_raw == pytest.approx(-Q, abs=40)


def test_23_home_switch_ahead() -> None:
    rig = layout(23, home=(Q, 2 * Q))
    run = home(rig)
    assert_homed(rig)
    assert max(run.raw) < 2 * Q  # turned back inside the switch
    assert not any(i & 0x2 for i in run.inputs)  # never reached P-OT
    assert run.end_raw == pytest.approx(Q, abs=40)  # the switch's lower edge


def test_23_reverses_at_p_ot_and_homes_on_the_lower_edge() -> None:
    rig = layout(23, p_ot=Q, home=(-2 * Q, -Q))
    run = home(rig)
    assert_homed(rig)
    assert any(i & 0x2 for i in run.inputs)  # "遇到限位开关，自动反向"
    assert min(run.rpm) == -FAST_RPM  # fast again after the reversal
    assert run.end_raw == pytest.approx(-2 * Q, abs=40)


def test_23_from_inside_the_home_switch() -> None:
    rig = layout(23, home=(-Q, Q))
    run = home(rig)
    assert_homed(rig)
    assert max(run.raw) <= 0
    assert min(run.rpm) == -SLOW_RPM
    assert run.end_raw == pytest.approx(-Q, abs=40)


def test_27_home_switch_ahead() -> None:
    rig = layout(27, home=(-2 * Q, -Q))
    run = home(rig)
    assert_homed(rig)
    assert min(run.raw) > -2 * Q
    assert run.end_raw == pytest.approx(-Q, abs=40)  # the switch's upper edge


def test_27_reverses_at_n_ot_and_homes_on_the_upper_edge() -> None:
    rig = layout(27, n_ot=-Q, home=(Q, 2 * Q))
    run = home(rig)
    assert_homed(rig)
    assert any(i & 0x1 for i in run.inputs)
    assert max(run.rpm) == FAST_RPM
    assert run.end_raw == pytest.approx(2 * Q, abs=40)


def test_27_from_inside_the_home_switch() -> None:
    rig = layout(27, home=(-Q, Q))
    run = home(rig)
    assert_homed(rig)
    assert min(run.raw) >= 0
    assert run.end_raw == pytest.approx(Q, abs=40)


def test_35_takes_the_current_position() -> None:
    rig = layout(35)
    run = home(rig)
    assert_homed(rig)
    assert run.raw == []  # done in the first period, nothing moved
    assert rig[0x6063] == round(HOME_OFFSET * INC / 100000)


def test_23_without_a_home_switch_in_the_travel_is_a_homing_error() -> None:
    rig = layout(23, n_ot=-Q, p_ot=Q)
    home(rig)
    assert rig.faults == [FaultKind.HOMING_ERROR]
    assert rig.statusword & (ATTAINED | ERROR) == ERROR


def test_17_meeting_p_ot_is_a_homing_error() -> None:
    # starts inside N-OT, P-OT before its edge (Kinco: limit switches fault one at a time)
    rig = layout(17, n_ot=2 * Q, p_ot=Q, config=KINCO_CONFIG)
    home(rig)
    assert rig.faults == [FaultKind.HOMING_ERROR]


def test_mdi_17_meeting_p_ot_inside_n_ot_is_alarm_7() -> None:
    # On the MDi both drive-inhibit inputs active at once is alarm 7, whatever the mode.
    rig = layout(17, n_ot=2 * Q, p_ot=Q)
    rig.controlword(0x1F)
    rig.run(2.0)  # slow + from inside N-OT: P-OT rises after 1.25 s
    assert rig.faults == [FaultKind.BOTH_LIMITS]


def test_homing_timeout_without_a_switch() -> None:
    rig = Rig(replace(MDI_CONFIG, homing_timeout_s=0.2), overrides={(0x6098, 0): 17})
    del rig.values.values[(0x5FF1, 0)]
    rig.enable(6)
    rig.controlword(0x1F)
    rig.run(0.19)
    assert rig.faults == []
    rig.run(0.02)
    assert rig.faults == [FaultKind.HOMING_ERROR]
    rig.run(0.1)
    assert rig.statusword & (ERROR | 0x004F) == ERROR | 0x0008  # bit 13 seen in Fault


@pytest.mark.parametrize("method", [19, 1, 0])
def test_unsupported_method_is_a_homing_error(method: int) -> None:
    rig = layout(method)
    home(rig)
    assert rig.faults == [FaultKind.HOMING_ERROR]


def test_method_not_offered_by_the_profile_is_a_homing_error() -> None:
    rig = Rig(replace(MDI_CONFIG, homing_methods=frozenset({35})), overrides={(0x6098, 0): 17})
    rig.enable(6)
    rig.controlword(0x1F)
    rig.step()
    assert rig.faults == [FaultKind.HOMING_ERROR]


def test_limit_switches_do_not_fault_while_homing() -> None:
    rig = layout(17, n_ot=-Q)
    home(rig)
    assert rig.faults == []


def test_halt_interrupts_homing() -> None:
    rig = layout(17)
    rig.controlword(0x1F)
    rig.run(0.1)
    rig.controlword(0x11F)
    rig.run(0.05)
    assert rig.statusword & (ATTAINED | ERROR | REACHED) == REACHED  # interrupted
    assert rig[0x606C] == 0
    assert rig.faults == []


def test_statusword_matches_python_canopen_homing_states() -> None:
    states = {name: bits for name, bits in CanopenHoming.STATES.items()}

    def state_of(word: int) -> str:
        return next(name for name, (mask, value) in states.items() if word & mask == value)

    rig = layout(17, n_ot=-Q)
    assert state_of(rig.statusword) == "INTERRUPTED"  # not started yet
    rig.controlword(0x1F)
    assert state_of(rig.statusword) == "IN PROGRESS"
    rig.run_until(ATTAINED, ATTAINED)
    assert state_of(rig.statusword) == "TARGET REACHED"


def test_reference_found_bit_15_on_kinco_only() -> None:
    mdi, kinco = layout(35), Rig(KINCO_CONFIG, overrides={(0x6098, 0): 35})
    kinco.enable(6)
    for rig in (mdi, kinco):
        assert not rig.statusword & 0x8000
        rig.controlword(0x1F)  # Kinco: 6040h = 1Fh starts homing (Kinco manual §5.4.6)
        rig.step()
    assert not mdi.statusword & 0x8000
    assert kinco.statusword & 0x8000
    kinco[0x6060] = 1  # stays set in any mode afterwards
    kinco.step()
    assert kinco.statusword & 0x8000


def test_homing_under_reversed_polarity_finds_the_same_switch() -> None:
    rig = layout(17, n_ot=-Q, x607E=1)
    run = home(rig)
    assert_homed(rig)
    assert run.end_raw == pytest.approx(-Q, abs=40)


def test_position_mode_after_homing_uses_the_new_origin() -> None:
    rig = layout(17, n_ot=-Q)
    home(rig)
    rig[0x6060] = 1
    rig[0x6081] = 100000
    rig[0x607A] = HOME_OFFSET + 50000
    rig.controlword(0x1F)
    rig.controlword(0x0F)
    rig.run(1.0)
    assert rig[0x6064] == HOME_OFFSET + 50000
    assert rig[0x6063] == pytest.approx((HOME_OFFSET + 50000) * INC / 100000, abs=1)
