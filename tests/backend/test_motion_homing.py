"""Homing 17/18/23/27/35 on each simulated drive ends at the right switch edge with the right
statusword bits. The switches are moved close (N-OT at −1 rev, P-OT at +2 rev, home switch at
its default +1 … +1.25 rev) to keep the runs short; where the axis stopped is checked in the
motor frame by sliding the switch edge across it and watching 60FDh."""

from __future__ import annotations

import pytest

from servodesk.models.motion import HomeRequest
from tests.backend.motion_rig import NODES, SIM_NEG_LIMIT, SIM_POS_LIMIT, MotionRig, motion_rig

pytestmark = pytest.mark.anyio

REV = 131072
N_OT, P_OT = -REV, 2 * REV
HOME_START, HOME_END = 0x5FF3, 0x5FF4  # SIM home switch start / end (motor increments)
HW = (REV, 163840)
EDGE_TOLERANCE = 1000  # increments (0.008 rev) at a 30 rpm creep
# method → (switch object to slide, its edge, input lit when the edge is moved past the axis)
EDGES = {
    17: (SIM_NEG_LIMIT, N_OT, "negative_limit", +1),  # homed just above N-OT
    18: (SIM_POS_LIMIT, P_OT, "positive_limit", -1),  # just below P-OT
    23: (HOME_START, HW[0], "home_switch", -1),  # just below the switch's lower edge
    27: (HOME_END, HW[1], "home_switch", +1),  # just above its upper edge
}


async def homed_at_edge(r: MotionRig, node: int, method: int) -> None:
    index, edge, lamp, side = EDGES[method]
    for shift, lit in ((side * EDGE_TOLERANCE, True), (-side * EDGE_TOLERANCE, False)):
        await r.write(node, index, 0, edge + shift)
        # 60FDh follows the moved switch at the drive's next control period and reaches the
        # state with its next TPDO: wait for it, a moment is not a measurement here
        await r.until(
            node,
            lambda s, lamp=lamp, lit=lit: s.inputs[lamp] is lit,  # type: ignore[misc]
            timeout=2,
            what=f"{lamp} {'lit' if lit else 'dark'} with the edge moved {shift} inc",
        )
    await r.write(node, index, 0, edge)


@pytest.mark.parametrize("method", [17, 18, 23, 27, 35])
async def test_homing_ends_at_the_right_place_with_the_right_bits(method: int) -> None:
    async with motion_rig() as r:
        for node in NODES:
            await r.write(node, SIM_NEG_LIMIT, 0, N_OT)
            await r.write(node, SIM_POS_LIMIT, 0, P_OT)
            await r.motion.enable(node)
            assert method in [m.method for m in r.motion.homing_methods(node)]
            request = HomeRequest(
                method=method, fast_rpm=300, slow_rpm=30, acceleration_rpm_s=3000, offset_inc=0
            )
            await r.motion.home(node, request)
            state = await r.until(
                node,
                lambda s: s.homing is not None and s.homing.phase != "running",
                timeout=10,
                what=f"homing {method}",
            )
            assert state.homing is not None
            assert state.homing.phase == "attained", state.homing
            bits = {b.bit: b.on for b in state.status_bits}
            assert bits[10]
            assert bits[12]
            assert not bits[13]
            assert state.homed is True
            if node == 2:
                assert state.statusword & 0x8000  # Kinco "reference found"
            assert abs(state.position_inc) <= EDGE_TOLERANCE  # 607Ch = 0 at home
            if method in EDGES:
                await homed_at_edge(r, node, method)


async def test_homing_offset_and_unknown_method() -> None:
    async with motion_rig() as r:
        node = 3
        await r.motion.enable(node)
        await r.motion.home(node, HomeRequest(method=35, offset_inc=26214))
        state = await r.until(
            node,
            lambda s: s.homing is not None and s.homing.phase == "attained",
            timeout=2,
            what="home",
        )
        assert abs(state.position_inc - 26214) <= 2  # user-unit rounding of 0.2 rev
        with pytest.raises(Exception, match="homing methods"):
            await r.motion.home(node, HomeRequest(method=1))
