"""Every mode the simulated drives support moves the axis as commanded: PP set-points with the
handshake (absolute, relative, queued, change immediately), PV at a speed, PT at a torque; the
limits refuse commands before anything is sent; stop halts a jog on the priority lane."""

from __future__ import annotations

import pytest

from servodesk.models.motion import MotionLimits, MoveQueueRequest, MoveRequest
from servodesk.motion.errors import LimitError, MotionBusyError
from tests.backend.motion_rig import NODES, MotionRig, motion_rig

pytestmark = pytest.mark.anyio

POSITION_WINDOW_INC = 132  # 6067h absent or default: 1/1000 rev = 100 user units


def reached(r: MotionRig, node: int, timeout: float = 5.0):  # type: ignore[no-untyped-def]
    return r.until(
        node,
        lambda s: s.move is not None and s.move.phase == "reached",
        timeout=timeout,
        what="target reached",
    )


async def test_pp_absolute_and_relative_moves_reach_their_targets() -> None:
    async with motion_rig() as r:
        for node in NODES:
            await r.motion.enable(node)
            await r.motion.move(node, MoveRequest(position_rev=0.5, velocity_rpm=600))
            state = await reached(r, node)
            assert abs(state.position_inc - 65536) <= POSITION_WINDOW_INC
            assert state.target_reached
            assert state.mode_display == "pp"
            step = MoveRequest(position_rev=-0.25, relative=True, velocity_rpm=600)
            await r.motion.move(node, step)
            state = await reached(r, node)
            assert abs(state.position_inc - 32768) <= POSITION_WINDOW_INC


async def test_pp_queue_runs_the_set_points_in_order() -> None:
    async with motion_rig() as r:
        for node in NODES:
            await r.motion.enable(node)
            moves = [MoveRequest(position_rev=p, velocity_rpm=900) for p in (0.2, -0.2, 0.3)]
            state = await r.motion.move_queue(node, MoveQueueRequest(moves=moves))
            assert state.move is not None
            assert state.move.queued == 2
            state = await r.until(
                node,
                lambda s: (
                    s.move is not None
                    and s.move.queued == 0
                    and s.move.phase == "reached"
                    and s.move.target_inc == 39322
                ),
                timeout=6,
                what="queue done",
            )
            assert abs(state.position_inc - 39322) <= POSITION_WINDOW_INC


@pytest.mark.parametrize("node", [2, 3])
async def test_pp_change_immediately_replaces_the_running_move(node: int) -> None:
    async with motion_rig() as r:
        await r.motion.enable(node)
        await r.motion.move(node, MoveRequest(position_rev=3.0, velocity_rpm=120))
        await r.until(node, lambda s: s.position_rev > 0.05, timeout=2, what="moving")
        now = MoveRequest(position_rev=0.1, velocity_rpm=120, immediately=True)
        await r.motion.move(node, now)
        state = await reached(r, node)
        assert abs(state.position_inc - 13107) <= POSITION_WINDOW_INC


async def test_pv_reaches_and_holds_the_speed_and_stop_halts_it() -> None:
    async with motion_rig() as r:
        for node in NODES:
            await r.widen_switches(node)
            await r.motion.enable(node)
            await r.motion.jog_start(node, "pv", 120.0, acceleration_rpm_s=2000)
            state = await r.until(
                node,
                lambda s: s.target_reached and abs(s.velocity_rpm - 120) <= 10,
                timeout=2,
                what="speed",
            )
            assert state.mode_display == "pv"
            for _ in range(5):  # holds it
                state = await r.motion.state(node)
                assert abs(state.velocity_rpm - 120) <= 10
            await r.motion.jog_update(node, -60.0)
            await r.until(node, lambda s: abs(s.velocity_rpm + 60) <= 10, timeout=2, what="new")
            await r.motion.stop(node, reason="test")
            state = await r.until(node, lambda s: abs(s.velocity_rpm) < 1, timeout=2, what="halt")
            assert state.state == "operation_enabled"
            assert state.status_bits[8].name
            assert state.controlword & 0x0100  # halt
            with pytest.raises(MotionBusyError):
                await r.motion.jog_update(node, 10.0)  # the stop ended the jog


async def test_pt_produces_the_torque_within_its_limit() -> None:
    async with motion_rig() as r:
        for node in NODES:
            await r.widen_switches(node)
            await r.motion.enable(node)
            await r.motion.jog_start(node, "pt", 5.0, torque_slope_pct_s=1000)
            state = await r.until(
                node,
                lambda s: s.torque_pct is not None and abs(s.torque_pct - 5.0) <= 0.5,
                timeout=2,
                what="torque",
            )
            assert state.mode_display == "pt"
            assert state.velocity_rpm > 0
            assert abs(state.velocity_rpm) <= state.limits.max_velocity_rpm
            await r.motion.stop(node, reason="test")
            await r.until(node, lambda s: abs(s.velocity_rpm) < 1, timeout=3, what="halt")


async def test_limits_refuse_before_anything_moves() -> None:
    async with motion_rig() as r:
        node = 1
        await r.motion.enable(node)
        assert r.motion.limits(node).max_velocity_rpm == 6000  # MDi PA-103
        assert r.motion.limits(2).max_velocity_rpm == 3000  # Kinco 6080h
        with pytest.raises(LimitError):
            r.motion.set_limits(node, MotionLimits(max_velocity_rpm=7000, max_torque_pct=100))
        r.motion.set_limits(
            node,
            MotionLimits(
                max_velocity_rpm=200, max_torque_pct=10, min_position_rev=-1, max_position_rev=1
            ),
        )
        with pytest.raises(LimitError):
            await r.motion.jog_start(node, "pv", 300.0)
        with pytest.raises(LimitError):
            await r.motion.jog_start(node, "pt", 20.0)
        with pytest.raises(LimitError):
            await r.motion.move(node, MoveRequest(position_rev=1.5, velocity_rpm=100))
        state = await r.motion.state(node)
        assert state.mode is None
        assert state.position_inc == 0
