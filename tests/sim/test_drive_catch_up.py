"""A drive's control loop runs on its own processor and never stalls; the simulated one runs on
a thread of a busy computer and may be polled late. It then runs the control periods it missed,
so a ramp takes as long in wall time however late the polls came, up to a quarter of a second
of missed time (beyond that — a debugger, a suspended laptop — the time is dropped, not run in
one burst)."""

from __future__ import annotations

import pytest

from servodesk_sim.drive import CATCH_UP_LIMIT_S
from tests.sim.drive_rig import DriveRig

CONTROLWORD, MODES, VELOCITY = 0x6040, 0x6060, 0x606C
PROFILE_ACCELERATION, TARGET_VELOCITY = 0x6083, 0x60FF
PV = 3


def ramping(profile: str, node: int) -> DriveRig:
    """Profile velocity towards 2 rev/s at 10 rev/s² (0.2 s of ramp), enabled."""
    rig = DriveRig(node, profile)
    rig.advance(0.01)
    rig.write_ok(MODES, 0, PV, 1)
    rig.write_ok(PROFILE_ACCELERATION, 0, 1000, 4)
    rig.write_ok(TARGET_VELOCITY, 0, 200000, 4)
    for word in (0x06, 0x07, 0x0F):
        rig.write_ok(CONTROLWORD, 0, word, 2)
        rig.advance(0.005)
    return rig


@pytest.mark.parametrize(("profile", "node"), [("cia402", 3), ("kinco", 2), ("mdi-s1c", 1)])
@pytest.mark.parametrize("poll_s", [0.02, 0.05, 0.1, CATCH_UP_LIMIT_S])
def test_late_polls_run_the_missed_periods(profile: str, node: int, poll_s: float) -> None:
    on_time, late = ramping(profile, node), ramping(profile, node)
    span = max(0.1, poll_s)  # inside the 0.2 s ramp, or one poll that late
    on_time.advance(span)
    late.advance(span, step=poll_s)
    assert late.read(VELOCITY) == on_time.read(VELOCITY) != 0


def test_a_stall_beyond_the_limit_drops_the_time() -> None:
    on_time, stalled = ramping("cia402", 3), ramping("cia402", 3)
    on_time.advance(CATCH_UP_LIMIT_S)
    stalled.advance(1.0, step=1.0)  # one poll after a second: a quarter of it is run
    assert stalled.read(VELOCITY) == on_time.read(VELOCITY)
