"""What the Drive page shows and does must be what the drive does (issue 17):

- an enable never resets an active fault: it is refused naming the fault, and nothing that
  resets it goes out (fault reset is its own, audited act);
- enabling reads only what the drive's dictionary has (no "aborted SDO 608Fh:01h" on the
  timeline);
- a PP move stopped by a quick stop ends (interrupted, with why), an attained homing stays
  attained when the drive changes mode, and the limits in force follow the drive's own
  max speed (MDi PA-103) when it is changed;
- the travel ends are named: the simulator's limit switches 5FF1h/5FF2h.
"""

from __future__ import annotations

import can
import pytest

from servodesk.models.motion import HomeRequest, MotionLimits, MoveProgress, MoveRequest
from servodesk.motion.axis import Axis, build_state
from servodesk.motion.drive_io import Snapshot
from servodesk.motion.errors import EnableBlockedError
from tests.backend.motion_rig import (
    MDI,
    NODES,
    SIM_INJECT_FAULT,
    SIM_NEG_LIMIT,
    SIM_POS_LIMIT,
    MotionRig,
    motion_rig,
)

pytestmark = pytest.mark.anyio

FOLLOWING_ERROR_FAULT = {1: 4, 2: 0x8611, 3: 0x8611}  # MDi alarm 4, CiA 402 8611h
FAULT_HEX = {1: "0x0004", 2: "0x8611", 3: "0x8611"}  # 603Fh as the API names it
SDO_RX, SDO_TX = 0x600, 0x580
SDO_ABORT = 0x80
CONTROLWORD = 0x6040  # Controlword
MAX_SPEED_PA103 = (0x2006, 8)  # MDi PA-103 maximum speed (MDi-S1-C CANopen manual table 2.31)
INC_PER_REV = 131072


def frames_since(listener: can.BusABC) -> list[can.Message]:
    """Every frame another bus sent on the channel since `listener` was opened."""
    frames = []
    while (msg := listener.recv(timeout=0)) is not None:
        frames.append(msg)
    return frames


def controlwords(frames: list[can.Message], node: int) -> list[int]:
    """The values of the SDO downloads to 6040h sent to `node`."""
    downloads = [
        bytes(m.data)
        for m in frames
        if m.arbitration_id == SDO_RX + node and len(m.data) == 8 and m.data[0] & 0xE0 == 0x20
    ]
    return [
        int.from_bytes(d[4:6], "little")
        for d in downloads
        if int.from_bytes(d[1:3], "little") == CONTROLWORD and d[3] == 0
    ]


def aborts(frames: list[can.Message], node: int) -> list[str]:
    return [
        f"{int.from_bytes(bytes(m.data[1:3]), 'little'):04X}h:{m.data[3]:02X}h"
        for m in frames
        if m.arbitration_id == SDO_TX + node and m.data and m.data[0] == SDO_ABORT
    ]


async def fault(r: MotionRig, node: int) -> None:
    await r.write(node, SIM_INJECT_FAULT, 0, FOLLOWING_ERROR_FAULT[node])
    await r.until(node, lambda s: s.state == "fault", timeout=2, what="fault")


# ---------------------------------------------------------------- 1. enable never resets a fault


async def test_enable_on_a_faulted_drive_is_refused_naming_the_fault() -> None:
    async with motion_rig() as r:
        for node in NODES:
            await fault(r, node)
            with can.Bus(interface="virtual", channel=r.rig.channel) as listener:
                with pytest.raises(EnableBlockedError) as blocked:
                    await r.motion.enable(node)
                sent = controlwords(frames_since(listener), node)
            assert not [w for w in sent if w & 0x0080], f"node {node} sent a fault reset: {sent}"
            reasons = blocked.value.reasons
            assert reasons[0].code == "fault", reasons
            assert FAULT_HEX[node] in reasons[0].message
            fault_info = blocked.value.state.fault
            assert fault_info is not None
            assert fault_info.name
            assert fault_info.name in reasons[0].message
            assert (await r.motion.state(node)).state == "fault"
            # the two acts the page offers: fault reset, then enable
            assert (await r.motion.fault_reset(node)).state == "switch_on_disabled"
            assert (await r.motion.enable(node)).state == "operation_enabled"


async def test_enable_operation_command_on_a_faulted_drive_sends_nothing() -> None:
    async with motion_rig() as r:
        await fault(r, MDI)
        with can.Bus(interface="virtual", channel=r.rig.channel) as listener:
            with pytest.raises(EnableBlockedError) as blocked:
                await r.motion.command(MDI, "enable_operation")
            assert controlwords(frames_since(listener), MDI) == []
        assert "fault" in [reason.code for reason in blocked.value.reasons]
        assert (await r.motion.state(MDI)).state == "fault"


# ---------------------------------------------------------------- 2. only what the dictionary has


async def test_enabling_makes_no_sdo_abort() -> None:
    async with motion_rig() as r:
        for node in NODES:
            with can.Bus(interface="virtual", channel=r.rig.channel) as listener:
                await r.motion.enable(node)
                await r.motion.state(node)
                await r.motion.disable(node)
                seen = aborts(frames_since(listener), node)
            assert seen == [], f"node {node} aborted SDO {seen}"


# ---------------------------------------------------------------- 3. no stale motion


async def test_a_quick_stopped_move_ends_interrupted_with_why() -> None:
    async with motion_rig() as r:
        for node in NODES:
            await r.widen_switches(node)
            await r.motion.enable(node)
            moving = await r.motion.move(node, MoveRequest(position_rev=30, velocity_rpm=600))
            assert moving.move is not None
            assert moving.move.phase == "moving"
            await r.motion.quick_stop(node)
            stopped = await r.until(
                node,
                lambda s: s.state != "operation_enabled" and abs(s.velocity_rpm) < 1,
                timeout=3,
                what="standstill after quick stop",
            )
            assert stopped.move is not None
            assert stopped.move.phase == "interrupted", stopped.move
            assert stopped.move.message
            assert "quick stop" in stopped.move.message
            # it stays ended when the drive is enabled again
            again = await r.motion.enable(node)
            assert again.move is not None
            assert again.move.phase == "interrupted"


async def test_attained_homing_stays_attained_after_a_mode_change() -> None:
    async with motion_rig() as r:
        for node in NODES:
            await r.motion.enable(node)
            await r.motion.home(node, HomeRequest(method=35))
            homed = await r.until(
                node,
                lambda s: s.homing is not None and s.homing.phase == "attained",
                timeout=3,
                what="homing attained",
            )
            assert homed.homing is not None
            state = await r.motion.set_mode(node, "pp")
            assert state.mode_display == "pp"
            assert state.homing is not None
            assert state.homing.phase == "attained", state.homing
            assert state.homed


async def test_limits_in_force_follow_the_drives_max_speed() -> None:
    async with motion_rig() as r:
        await r.motion.enable(MDI)
        assert r.motion.limits(MDI).max_velocity_rpm > 300
        # PA-103 written as the Parameters page (or anyone on the bus) would
        await r.write(MDI, *MAX_SPEED_PA103, 300, 2)
        state = await r.until(
            MDI,
            lambda s: s.limits.max_velocity_rpm == 300,
            timeout=3,
            what="limits following PA-103 = 300",
        )
        assert state.drive_limits is not None
        assert state.drive_limits.max_velocity_rpm == 300
        assert "PA-103" in state.drive_limits.velocity_source
        assert r.motion.limits(MDI).max_velocity_rpm == 300
        await r.write(MDI, *MAX_SPEED_PA103, 3000, 2)
        back = await r.until(
            MDI,
            lambda s: s.limits.max_velocity_rpm == 3000,
            timeout=3,
            what="limits following PA-103 = 3000",
        )
        assert back.limits.max_velocity_rpm == 3000


# ---------------------------------------------------------------- 4. where the travel ends


async def test_the_travel_ends_are_named() -> None:
    async with motion_rig() as r:
        for node in NODES:
            await r.write(node, SIM_NEG_LIMIT, 0, -4 * INC_PER_REV)
            await r.write(node, SIM_POS_LIMIT, 0, 6 * INC_PER_REV)
            state = await r.until(
                node,
                lambda s: s.travel is not None and s.travel.switches is not None,
                timeout=3,
                what="travel ends",
            )
            assert state.travel is not None
            assert state.travel.switches is not None
            switches = state.travel.switches
            assert (switches.min_rev, switches.max_rev) == (-4.0, 6.0)
            assert switches.simulator
            assert "5FF1h" in switches.source
            assert "5FF2h" in switches.source
            # none of the three simulated drives has 607Dh Software position limit
            assert state.travel.software_limit is None


def test_a_move_stopped_by_servodesk_says_why_before_the_drive_shows_it() -> None:
    """A reading taken between the quick stop being decided and the drive showing it (still
    Operation enabled, controlword 000Fh) names the quick stop, not "another command"."""
    axis = Axis(node=1, limits=MotionLimits(max_velocity_rpm=3000, max_torque_pct=100))
    axis.move = MoveProgress(target_inc=393216, phase="moving", queued=0)
    axis.dropped_by = "stopped by quick stop (controlword bit 2 = 0)"
    still_enabled = Snapshot(
        statusword=0x0237,
        controlword=0x000F,
        mode=1,
        mode_display=1,
        position=1000,
        velocity=300,
        torque=0,
        following_error=0,
        inputs=0,
        error_code=0,
    )
    state = build_state(axis, still_enabled, nmt_state="operational", data=None, fault_source="")
    assert state.move is not None
    assert state.move.phase == "interrupted"
    assert state.move.message == "stopped by quick stop (controlword bit 2 = 0)"


@pytest.mark.parametrize(
    ("statusword", "phase"),
    [
        (0x0C37, "interrupted"),  # at rest (bit 10) and held by a limit (bit 11): stopped there
        (0x0837, "moving"),  # still moving off a limit switch (bit 11 without bit 10)
        (0x0437, "moving"),  # bit 10 short of the target, no limit: the drive still settles
    ],
)
def test_a_move_held_at_a_limit_short_of_its_target_says_so(statusword: int, phase: str) -> None:
    """The MDi-S1-C stops a move at a drive-inhibit input without a fault: the move ends
    interrupted, naming the limit, instead of "moving" for ever."""
    axis = Axis(node=1, limits=MotionLimits(max_velocity_rpm=3000, max_torque_pct=100))
    axis.move = MoveProgress(target_inc=393216, phase="moving", queued=0)
    axis.target_user = 3000
    held = Snapshot(
        statusword=statusword,
        controlword=0x001F,
        mode=1,
        mode_display=1,
        position=1200,
        velocity=0,
        torque=0,
        following_error=0,
        inputs=0,
        error_code=0,
    )
    state = build_state(axis, held, nmt_state="operational", data=None, fault_source="")
    assert state.move is not None
    assert state.move.phase == phase
    if phase == "interrupted":
        assert state.move.message is not None
        assert "stopped at a limit" in state.move.message


@pytest.mark.parametrize(
    ("taken_at", "statusword", "phase"),
    [
        (9.5, 0x0637, None),  # begun before the drive took the start: shows the drive before it
        (10.5, 0x0637, "interrupted"),  # after it: bit 10 without bit 12, not started
        (None, 0x0637, "interrupted"),  # a reading of just now
        (9.5, 0x1637, None),  # even attained bits wait for a reading from after the start
        (10.5, 0x1637, "attained"),
        (10.5, 0x0237, "running"),
    ],
)
def test_a_reading_begun_before_the_homing_start_does_not_end_the_run(
    taken_at: float | None, statusword: int, phase: str | None
) -> None:
    """A page's reading that began before the drive took the homing start and finished after
    it still shows the drive at rest (bit 10 without bit 12): the run must not end
    "interrupted" on it, and the card shows nothing until a reading from after the start."""
    axis = Axis(node=3, limits=MotionLimits(max_velocity_rpm=3000, max_torque_pct=100))
    axis.homing_method, axis.homing_since = 35, 10.0
    reading = Snapshot(
        statusword=statusword,
        controlword=0x001F,
        mode=6,
        mode_display=6,
        position=0,
        velocity=0,
        torque=0,
        following_error=0,
        inputs=0,
        error_code=0,
        taken_at=taken_at,
    )
    state = build_state(axis, reading, nmt_state="operational", data=None, fault_source="")
    assert (state.homing.phase if state.homing else None) == phase
