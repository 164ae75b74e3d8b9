"""A drive at rest and unpowered skips its control periods (MotionCore.step), which must change
nothing anyone can see: every write and command still shows at the next period."""

from __future__ import annotations

from tests.sim.drive_rig import DriveRig

CONTROLWORD, STATUSWORD = 0x6040, 0x6041
MODES, MODES_DISPLAY = 0x6060, 0x6061
POSITION, VELOCITY = 0x6064, 0x606C
DIGITAL_INPUTS = 0x60FD
P_OT = 0x5FF2  # the simulator's positive limit switch position (motor increments)
PV = 3


def changes(rig: DriveRig) -> int:
    return rig.drive.store.changes


def test_a_drive_left_alone_publishes_nothing_new() -> None:
    rig = DriveRig(3, "cia402")
    rig.advance(0.05)
    before = changes(rig)
    rig.advance(0.5)
    assert changes(rig) == before


def test_writes_at_rest_still_show_at_the_next_period() -> None:
    rig = DriveRig(3, "cia402")
    rig.advance(0.05)
    rig.write_ok(MODES, 0, PV, 1)
    rig.advance(0.002)
    assert rig.read(MODES_DISPLAY) == PV
    assert rig.read(DIGITAL_INPUTS) & 0x2 == 0
    rig.write_ok(P_OT, 0, 0, 4)  # the positive limit switch moved onto the axis
    rig.advance(0.002)
    assert rig.read(DIGITAL_INPUTS) & 0x2  # 60FDh bit 1: positive limit switch
    rig.write_ok(CONTROLWORD, 0, 0x06, 2)  # shutdown: ready to switch on
    rig.advance(0.002)
    assert rig.read(STATUSWORD) & 0x6F == 0x21


def test_a_coasting_motor_comes_to_rest_and_then_stays() -> None:
    rig = DriveRig(3, "cia402")
    rig.write_ok(MODES, 0, PV, 1)
    rig.write_ok(0x60FF, 0, 200000, 4)  # two revolutions a second
    for word in (0x06, 0x07, 0x0F):
        rig.write_ok(CONTROLWORD, 0, word, 2)
    rig.advance(1.0)
    assert rig.read(VELOCITY) != 0
    rig.write_ok(CONTROLWORD, 0, 0x00, 2)  # disable voltage: the motor coasts
    rig.advance(30.0, step=0.01)
    assert rig.read(VELOCITY) == 0
    position, before = rig.read(POSITION), changes(rig)
    rig.advance(1.0)
    assert (rig.read(POSITION), changes(rig)) == (position, before)
