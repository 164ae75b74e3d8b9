"""Limit switches as each drive's manual has them.

MDi-S1-C (CANopen manual §4.1): alarm 7 "驱动禁止异常" is "CCW/CW 驱动禁止输入都 OFF", both
drive-inhibit inputs at once. Running into one of them (P-OT or N-OT) stops the motion toward it
without an alarm: statusword bit 11 "internal limit active" shows it, and the axis still moves
the other way. Kinco (Kinco servo CANopen manual §8 FAULT_PLOCK_BIT / FAULT_NLOCK_BIT) and the
generic CiA 402 drive fault with 8613h / 8612h on one switch, as before.

First the motion core on a 1 ms fake clock, then whole drives frame for frame.
"""

from __future__ import annotations

import pytest

from servodesk_data.fault_kind import FaultKind
from servodesk_protocol.cia402 import Cia402State
from servodesk_sim.frames import Frame
from servodesk_sim.motion import MotionConfig
from tests.sim.drive_rig import DriveRig
from tests.sim.motion_rig import CIA402_CONFIG, INC, KINCO_CONFIG, REV, Rig

S = Cia402State
INTERNAL_LIMIT = 0x0800  # statusword bit 11
N_OT, P_OT = 0x1, 0x2  # 60FDh bits
RPM = REV // 60  # user units/s per rpm with the default gear ratio
SWITCHES = {(0x5FF1, 0): -INC // 2, (0x5FF2, 0): INC // 2}  # N-OT −0.5 rev, P-OT +0.5 rev


def _position_rev(rig: Rig) -> float:
    return rig[0x6064] / REV


# ----------------------------------------------------------------------------- motion core


@pytest.mark.parametrize(
    ("rpm", "switch"), [(600, P_OT), (-600, N_OT)], ids=["into P-OT", "into N-OT"]
)
def test_mdi_stops_at_one_inhibit_input_without_alarm_and_moves_back(rpm: int, switch: int) -> None:
    rig = Rig(overrides=SWITCHES)  # MDi-S1-C
    rig.enable(3)  # profile velocity
    rig[0x60FF] = rpm * RPM
    rig.run(0.3)
    assert rig.faults == []
    assert rig.state is S.OPERATION_ENABLED
    assert rig[0x606C] == 0  # stopped …
    assert 0.5 <= abs(_position_rev(rig)) < 0.6  # … just past the switch (10 ms of braking)
    assert rig[0x60FD] & switch
    assert rig.statusword & INTERNAL_LIMIT
    rig.run(0.5)  # still asking for that direction: it stays where it is
    assert rig.faults == []
    assert 0.5 <= abs(_position_rev(rig)) < 0.6
    rig[0x60FF] = -rpm // 10 * RPM  # the other way, 1 rev/s
    rig.run(0.3)
    assert rig.faults == []
    assert 0.1 < abs(_position_rev(rig)) < 0.5
    assert rig[0x60FD] & switch == 0
    assert rig.statusword & INTERNAL_LIMIT == 0


def test_mdi_profile_position_move_ends_at_the_inhibit_and_the_next_goes_back() -> None:
    rig = Rig(overrides=SWITCHES)
    rig.enable(1)
    rig[0x6081] = 600 * RPM
    rig[0x607A] = 2 * REV  # beyond P-OT at +0.5 rev
    rig.controlword(0x1F)
    rig.controlword(0x0F)
    rig.run(0.5)
    assert rig.faults == []
    assert rig[0x606C] == 0
    assert 0.5 <= _position_rev(rig) < 0.6
    assert rig.statusword & INTERNAL_LIMIT
    assert rig.statusword & 0x1000 == 0  # the move is dropped: a new set-point is taken
    rig[0x607A] = 0
    rig.controlword(0x1F)
    rig.controlword(0x0F)
    rig.run(0.5)
    assert rig.faults == []
    assert rig[0x6064] == 0
    assert rig.statusword & INTERNAL_LIMIT == 0


def test_mdi_torque_into_an_inhibit_input_is_held() -> None:
    rig = Rig(overrides=SWITCHES)
    rig.enable(4)  # profile torque
    rig[0x6071] = 20  # 2 % rated torque toward P-OT
    rig.run(1.0)
    assert rig.faults == []
    assert rig[0x60FD] & P_OT
    assert 0.5 <= _position_rev(rig) < 0.7
    assert abs(rig[0x606C]) <= 1
    rig[0x6071] = -20
    rig.run(0.5)
    assert _position_rev(rig) < 0.5  # away from P-OT


@pytest.mark.parametrize("mode", [1, 3, 4, 6], ids=["pp", "pv", "pt", "hm"])
def test_mdi_both_inhibit_inputs_while_enabled_is_alarm_7(mode: int) -> None:
    both = {(0x5FF1, 0): INC, (0x5FF2, 0): -INC}  # the axis at 0 is inside both
    rig = Rig(overrides=both)
    rig.run(0.1)  # not enabled: the inputs alone raise nothing
    assert rig.faults == []
    assert rig[0x60FD] & (N_OT | P_OT) == N_OT | P_OT
    rig.enable(mode)
    rig.step()
    assert rig.faults == [FaultKind.BOTH_LIMITS]
    assert rig.state in (S.FAULT_REACTION_ACTIVE, S.FAULT)


@pytest.mark.parametrize("config", [KINCO_CONFIG, CIA402_CONFIG], ids=["kinco", "cia402"])
def test_fault_drives_keep_faulting_on_one_switch_and_have_no_bit_11(
    config: MotionConfig,
) -> None:
    rig = Rig(config, overrides=SWITCHES)
    rig.enable(3)
    rig[0x60FF] = 600 * RPM
    rig.run(0.3)
    assert rig.faults == [FaultKind.POSITIVE_LIMIT]
    assert rig.statusword & INTERNAL_LIMIT == 0


# ----------------------------------------------------------------------------- whole drives

NODE = 1
EMCY = 0x80 + NODE


def _emcys(frames: list[Frame]) -> list[str]:
    return [f.data.hex(" ").upper() for f in frames if f.can_id == EMCY]


def _enable_pv(rig: DriveRig, rpm: int) -> list[Frame]:
    frames = rig.send(0x600 + NODE, "2F 60 60 00 03 00 00 00")  # 6060h = 3
    value = (rpm * RPM).to_bytes(4, "little", signed=True).hex()
    frames += rig.send(0x600 + NODE, f"23 FF 60 00 {value}")  # 60FFh
    for word in ("06", "07", "0F"):
        frames += rig.send(0x600 + NODE, f"2B 40 60 00 {word} 00 00 00")
    return frames


# profile, the EMCY data for running into P-OT ([] = none)
DRIVES = [
    ("mdi-s1c", []),  # a drive-inhibit input: stop, no alarm (MDi-S1-C manual §4.1 alarm 7)
    ("kinco", ["13 86 00 00 00 00 00 00"]),  # Kinco servo CANopen manual §8 FAULT_PLOCK_BIT
    ("cia402", ["13 86 21 00 00 00 00 00"]),  # 8613h, error register 21h
]


@pytest.mark.parametrize(("profile", "into_p_ot"), DRIVES, ids=[d[0] for d in DRIVES])
def test_a_drive_running_into_p_ot(profile: str, into_p_ot: list[str]) -> None:
    rig = DriveRig(NODE, profile)
    rig.write_ok(0x5FF2, 0, INC // 2, 4)  # P-OT half a revolution ahead
    frames = _enable_pv(rig, 600)
    frames += rig.advance(0.5)
    assert _emcys(frames) == into_p_ot
    assert rig.read(0x60FD) & P_OT
    if into_p_ot:  # a fault: the drive ends in Fault with 603Fh = the code
        assert rig.read(0x6041) & 0x4F == 0x08
        assert rig.read(0x603F) == 0x8613
        return
    assert rig.read(0x6041) & 0x6F == 0x27  # still Operation enabled …
    assert rig.read(0x6041) & INTERNAL_LIMIT  # … held by the inhibit input
    assert rig.read(0x603F) == 0
    assert rig.read(0x606C) == 0
    stopped_at = rig.read(0x6064)
    assert REV // 2 <= stopped_at < REV * 6 // 10
    rig.write_ok(0x60FF, 0, (-60 * RPM) & 0xFFFFFFFF, 4)  # back the other way, 1 rev/s
    frames = rig.advance(0.3)
    assert _emcys(frames) == []
    assert rig.read(0x6064) < stopped_at - REV // 4
    assert rig.read(0x60FD) & P_OT == 0


def test_mdi_both_inhibit_inputs_while_enabled_send_alarm_7() -> None:
    rig = DriveRig(NODE, "mdi-s1c")
    rig.write_ok(0x5FF1, 0, INC, 4)  # N-OT active at or below +1 rev: at 0 it is active
    rig.write_ok(0x5FF2, 0, (-INC) & 0xFFFFFFFF, 4)  # P-OT active at or above −1 rev: too
    assert _emcys(rig.advance(0.1)) == []  # not enabled: no alarm
    frames = _enable_pv(rig, 0)
    frames += rig.advance(0.1)
    assert _emcys(frames) == ["07 00"]  # alarm 7, the 2-byte alarm number (manual §2.7)
    assert rig.read(0x603F) == 7
    assert rig.read(0x6041) & 0x4F == 0x08  # Fault
