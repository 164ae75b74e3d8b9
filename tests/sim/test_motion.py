"""MotionCore as the drive uses it: state changes on controlword writes, quick stop options,
fault reaction and reset, the overspeed / following-error / limit-switch monitors, mode display,
and the feedback objects."""

from __future__ import annotations

import pytest

from servodesk_data.fault_kind import FaultKind
from servodesk_protocol.cia402 import Cia402State
from servodesk_sim.motion import MotionConfig
from tests.sim.motion_rig import CIA402_CONFIG, INC, KINCO_CONFIG, MDI_CONFIG, REV, Rig

S = Cia402State


def test_statusword_shows_each_state_right_after_the_write() -> None:
    rig = Rig()
    assert rig.statusword == 0x0250  # Switch on disabled after power-up
    seen = []
    for word in (0x06, 0x07, 0x0F, 0x07, 0x06, 0x00):
        rig.controlword(word)  # no control period in between
        seen.append(rig.statusword & 0x027F)
    assert seen == [0x0231, 0x0233, 0x0237, 0x0233, 0x0231, 0x0250]


def test_switch_on_with_bit_3_goes_straight_to_operation_enabled() -> None:
    rig = Rig()
    rig.controlword(0x06)
    rig.controlword(0x0F)
    assert rig.state is S.OPERATION_ENABLED


def test_fault_reset_bit_left_high_blocks_enabling() -> None:
    rig = Rig()
    rig.controlword(0x86)
    assert rig.state is S.SWITCH_ON_DISABLED


def spin(rig: Rig, rpm: int) -> None:
    rig.enable(3)
    rig[0x60FF] = rpm * REV // 60
    rig.run(0.2)
    assert rig[0x606C] == rpm


@pytest.mark.parametrize(
    ("option", "stop_time", "ends_in"),
    [
        (1, 0.6, S.SWITCH_ON_DISABLED),  # 6084h slow-down ramp, then disabled
        (2, 0.06, S.SWITCH_ON_DISABLED),  # 6085h quick-stop ramp, then disabled
        (5, 0.6, S.QUICK_STOP_ACTIVE),  # 6084h, stay in quick stop
        (6, 0.06, S.QUICK_STOP_ACTIVE),  # 6085h, stay in quick stop
    ],
)
def test_quick_stop_option_picks_ramp_and_end_state(
    option: int, stop_time: float, ends_in: Cia402State
) -> None:
    rig = Rig(overrides={(0x605A, 0): option, (0x6084, 0): 1000, (0x6085, 0): 10000})
    spin(rig, 360)  # 6 rev/s = 600000 units/s: 0.6 s at 1e6 units/s², 0.06 s at 1e7
    rig.controlword(0x02)
    assert rig.state is S.QUICK_STOP_ACTIVE
    rig.run(stop_time * 0.8)
    assert rig.state is S.QUICK_STOP_ACTIVE
    assert rig[0x606C] > 0  # still braking
    rig.run(stop_time * 0.2 + 0.01)
    assert rig.state is ends_in
    assert rig[0x606C] == 0
    assert rig.faults == []


@pytest.mark.parametrize(
    ("option", "ends_in"), [(3, S.SWITCH_ON_DISABLED), (7, S.QUICK_STOP_ACTIVE)]
)
def test_quick_stop_at_the_torque_limit(option: int, ends_in: Cia402State) -> None:
    rig = Rig(CIA402_CONFIG, overrides={(0x605A, 0): option, (0x6072, 0): 500})
    spin(rig, 360)
    rig.controlword(0x02)
    torques = []
    for _ in range(20):
        rig.step()
        torques.append(rig[0x6077])
    assert -500 <= min(torques) < -450  # braking with (nearly) all the torque 6072h allows
    assert rig.state is ends_in
    rig.run(0.05)
    assert rig[0x606C] == 0


def test_quick_stop_option_0_disables_at_once_and_coasts() -> None:
    rig = Rig(overrides={(0x605A, 0): 0})
    spin(rig, 360)
    rig.controlword(0x02)
    assert rig.state is S.SWITCH_ON_DISABLED
    rig.run(0.05)
    assert rig[0x6077] == 0
    assert 300 < rig[0x606C] < 360  # friction only


def test_enable_operation_leaves_quick_stop_when_option_stays() -> None:
    rig = Rig(overrides={(0x605A, 0): 6})
    spin(rig, 60)
    rig.controlword(0x02)
    rig.run(0.05)
    rig.controlword(0x0F)
    assert rig.state is S.OPERATION_ENABLED  # transition 16
    rig.run(0.2)
    assert rig[0x606C] == 60  # the mode runs again


def test_quick_stop_request_from_the_drive() -> None:
    rig = Rig(overrides={(0x605A, 0): 2})
    spin(rig, 60)
    rig.core.quick_stop()
    assert rig.statusword & 0x006F == 0x0007  # Quick stop active
    rig.run(0.05)
    assert rig.statusword & 0x004F == 0x0040  # then Switch on disabled (605Ah = 2)


def test_disable_switches_the_power_stage_off() -> None:
    rig = Rig()
    spin(rig, 60)
    rig.core.disable()
    assert rig.statusword & 0x006F == 0x0040
    rig.step()
    assert rig[0x6077] == 0


def test_fault_reaction_brakes_then_shows_fault() -> None:
    rig = Rig(overrides={(0x6085, 0): 10000})
    spin(rig, 360)
    rig.core.enter_fault()
    assert rig.statusword & 0x004F == 0x000F  # Fault reaction active
    rig.run(0.05)
    assert rig.state is S.FAULT_REACTION_ACTIVE
    rig.run(0.02)
    assert rig.statusword & 0x004F == 0x0008
    assert rig[0x606C] == 0


def test_fault_while_not_enabled_is_fault_at_once() -> None:
    rig = Rig()
    rig.controlword(0x06)
    rig.core.enter_fault()
    assert rig.state is S.FAULT


def test_fault_reset_acts_on_the_rising_edge_only() -> None:
    rig = Rig()
    rig.enable(1)
    rig.core.enter_fault()
    rig.run(0.01)
    rig.faults_persist = True
    rig.controlword(0x80)  # edge, but the drive still has a fault
    assert rig.state is S.FAULT
    assert rig.resets == 1
    rig.faults_persist = False
    rig.controlword(0x80)  # held high: no edge, no reset attempt
    assert rig.resets == 1
    assert rig.state is S.FAULT
    rig.controlword(0x00)
    rig.controlword(0x80)
    assert rig.resets == 2
    assert rig.statusword & 0x024F == 0x0240


def test_overspeed_trips_above_the_max_speed_object() -> None:
    rig = Rig(overrides={(0x2006, 8): 1000})
    rig.enable(3)
    rig[0x60FF] = 1100 * REV // 60
    rig.run(0.005)
    assert rig.statusword & 0x2000  # PV bit 13: target above the limit
    rig.run(0.2)
    assert rig.faults == [FaultKind.OVERSPEED]
    rig.run(0.2)
    assert rig.state is S.FAULT


def test_running_at_the_max_speed_is_no_overspeed() -> None:
    rig = Rig(CIA402_CONFIG, overrides={(0x6080, 0): 1000, (0x2006, 8): 9999})
    rig.enable(3)
    rig[0x60FF] = 1000 * REV // 60
    rig.run(0.3)
    assert rig[0x606C] == 1000
    assert rig.faults == []
    assert not rig.statusword & 0x2000


def test_following_error_trips_above_6065() -> None:
    # 2 % torque cannot follow a 1e8 units/s² profile: the position falls behind.
    rig = Rig(overrides={(0x6072, 0): 20, (0x6065, 0): 5000, (0x6081, 0): 1000000})
    rig.enable(1)
    rig[0x607A] = 3 * REV
    rig.controlword(0x1F)
    rig.run(0.1)
    assert rig.faults == [FaultKind.FOLLOWING_ERROR]
    assert rig.statusword & 0x2000  # PP bit 13 stays visible in the fault
    assert abs(rig[0x60F4]) > 5000 or rig.state is not S.OPERATION_ENABLED


def test_following_error_window_absent_uses_three_revolutions() -> None:
    # 0.5 % torque accelerates at ~10 rev/s² while the demand runs at 10 rev/s.
    rig = Rig(overrides={(0x6072, 0): 5, (0x6081, 0): 10 * REV})
    del rig.values.values[(0x6065, 0)]
    rig.enable(1)
    rig[0x607A] = 20 * REV
    rig.controlword(0x1F)
    errors = []
    for _ in range(1000):
        rig.step()
        errors.append(abs(rig[0x60F4]))
        if rig.faults:
            break
    assert rig.faults == [FaultKind.FOLLOWING_ERROR]
    assert 3 * REV - 2000 < max(errors[:-1]) <= 3 * REV


@pytest.mark.parametrize("config", [KINCO_CONFIG, CIA402_CONFIG], ids=["kinco", "cia402"])
@pytest.mark.parametrize(
    ("rpm", "fault"), [(600, FaultKind.POSITIVE_LIMIT), (-600, FaultKind.NEGATIVE_LIMIT)]
)
def test_running_into_a_limit_switch_faults(
    config: MotionConfig, rpm: int, fault: FaultKind
) -> None:
    rig = Rig(config, overrides={(0x5FF1, 0): -INC // 2, (0x5FF2, 0): INC // 2})
    rig.enable(3)
    rig[0x60FF] = rpm * REV // 60
    rig.run(0.2)
    assert rig.faults == [fault]
    switch = 0x2 if rpm > 0 else 0x1
    assert rig[0x60FD] & switch


def test_leaving_a_limit_switch_is_allowed_and_reentering_faults() -> None:
    rig = Rig(KINCO_CONFIG, overrides={(0x5FF2, 0): INC // 2})
    rig.enable(3)
    rig[0x60FF] = 600 * REV // 60
    rig.run(0.2)
    assert rig.faults == [FaultKind.POSITIVE_LIMIT]
    rig.run(0.2)
    rig.controlword(0x80)
    rig[0x60FF] = -60 * REV // 60
    rig.enable()
    assert rig[0x60FD] & 0x2  # standing in P-OT
    rig.run(0.5)
    assert rig.faults == [FaultKind.POSITIVE_LIMIT]  # moving away is fine
    rig[0x60FF] = 60 * REV // 60
    rig.run(0.5)
    assert rig.faults == [FaultKind.POSITIVE_LIMIT, FaultKind.POSITIVE_LIMIT]


@pytest.mark.parametrize(
    ("config", "shown"), [(MDI_CONFIG, 0), (CIA402_CONFIG, 1)], ids=["mdi", "cia402"]
)
def test_unsupported_mode_display(config: MotionConfig, shown: int) -> None:
    rig = Rig(config)
    rig.enable(1)
    assert rig[0x6061] == 1
    rig[0x6060] = 2  # velocity mode: not in 6502h
    rig.step()
    assert rig[0x6061] == shown


def test_unsupported_mode_holds_the_axis() -> None:
    rig = Rig()
    rig.enable(2)
    assert rig[0x6061] == 0
    rig.run(0.1)
    assert rig.state is S.OPERATION_ENABLED
    assert rig[0x6064] == 0
    assert rig[0x6041] & 0x3400 == 0


def test_mode_change_while_enabled_takes_over_the_axis() -> None:
    rig = Rig()
    spin(rig, 120)
    rig[0x6060] = 1  # to profile position: stand still where the axis is
    rig.run(0.3)
    assert rig[0x6061] == 1
    assert rig[0x606C] == 0
    assert rig.faults == []


def test_feedback_objects_follow_gear_ratio_and_polarity() -> None:
    rig = Rig(overrides={(0x6091, 2): 10000, (0x607E, 0): 1})
    rig.enable(1)
    rig[0x607A] = 5000  # half a revolution in user units of 10000 per rev
    rig[0x6081] = 20000
    rig.controlword(0x1F)
    rig.run(0.5)
    assert rig[0x6064] == 5000
    assert rig[0x6063] == -INC // 2  # reversed polarity turns the motor the other way
    assert rig[0x60F4] == 0


def test_switch_inputs_are_published() -> None:
    rig = Rig(overrides={(0x5FF3, 0): -100, (0x5FF4, 0): 100})
    rig.step()
    assert rig[0x60FD] == 0x4  # standing on the home switch
    rig[0x5FF1] = 10
    rig.step()
    assert rig[0x60FD] == 0x5


def test_max_speed_unit_must_be_rpm() -> None:
    with pytest.raises(ValueError, match="rpm only"):
        MotionConfig(frozenset(), frozenset(), False, None, False, (0x6080, 0, "inc/s"))
