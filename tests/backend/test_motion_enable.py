"""Enabling, disabling, quick stop and fault reset on each simulated drive (1 MDi-S1-C,
2 Kinco, 3 CiA 402), and "why won't it enable" naming the cause from the drive's objects."""

from __future__ import annotations

import pytest

from servodesk.models.motion import MoveRequest
from servodesk.models.network import NmtCommandName
from servodesk.motion.errors import EnableBlockedError
from tests.backend.motion_rig import NODES, SIM_INJECT_FAULT, MotionRig, motion_rig

pytestmark = pytest.mark.anyio

CONTROLWORD = 0x6040  # Controlword
QUICK_STOP_OPTION = 0x605A  # Quick stop option code
FOLLOWING_ERROR_FAULT = {1: 4, 2: 0x8611, 3: 0x8611}  # MDi alarm 4, CiA 402 8611h
STAY_IN_QUICK_STOP = 6  # 605Ah: quick stop ramp, then stay in Quick stop active


async def to_start_state(r: MotionRig, node: int, start: str) -> None:
    """Bring the drive into `start` with raw SDO writes (not through the service)."""
    cw = {"switch_on_disabled": [], "ready_to_switch_on": [6], "switched_on": [6, 7]}
    if start in cw:
        for word in cw[start]:
            await r.write(node, CONTROLWORD, 0, word, 2)
    elif start == "operation_enabled":
        for word in (6, 7, 15):
            await r.write(node, CONTROLWORD, 0, word, 2)
    elif start == "quick_stop_active":
        await r.write(node, QUICK_STOP_OPTION, 0, STAY_IN_QUICK_STOP, 2)
        for word in (6, 7, 15, 2):
            await r.write(node, CONTROLWORD, 0, word, 2)
    elif start == "fault":
        await r.write(node, SIM_INJECT_FAULT, 0, FOLLOWING_ERROR_FAULT[node])
    await r.until(node, lambda s: s.state == start, timeout=2, what=start)


# Fault is not among them: an enable refuses it, naming the fault (test_motion_drive_page.py)
START_STATES = [
    "switch_on_disabled",
    "ready_to_switch_on",
    "switched_on",
    "operation_enabled",
    "quick_stop_active",
]


@pytest.mark.parametrize("start", START_STATES)
async def test_enable_from_every_start_state(start: str) -> None:
    async with motion_rig() as r:
        for node in NODES:
            await to_start_state(r, node, start)
            state = await r.motion.enable(node)
            assert state.state == "operation_enabled", (node, start)
            assert state.status_bits[2].on  # operation enabled
            assert not state.controlword & 0x0080  # fault reset bit left low
            if start != "operation_enabled":
                assert state.last_transition in ("enable operation (4)", "enable operation (16)")


async def test_disable_and_quick_stop() -> None:
    async with motion_rig() as r:
        for node in NODES:
            await r.motion.enable(node)
            state = await r.motion.disable(node)
            assert state.state == "ready_to_switch_on"
            assert state.last_transition == "shutdown (8)"
            await r.write(node, QUICK_STOP_OPTION, 0, STAY_IN_QUICK_STOP, 2)
            await r.motion.enable(node)
            await r.motion.quick_stop(node)
            state = await r.until(
                node, lambda s: s.state == "quick_stop_active", timeout=2, what="qs"
            )
            assert state.last_transition == "quick stop (11)"
            assert not state.status_bits[5].on  # bit 5 = 0 while quick stop is active


async def test_fault_reset_is_a_real_edge_of_bit_7() -> None:
    async with motion_rig() as r:
        for node in NODES:
            # bit 7 already high when the fault comes: a plain 0080h write would be no edge
            await r.write(node, CONTROLWORD, 0, 0x80, 2)
            await r.write(node, SIM_INJECT_FAULT, 0, FOLLOWING_ERROR_FAULT[node])
            faulted = await r.until(node, lambda s: s.state == "fault", timeout=2, what="fault")
            assert faulted.fault is not None
            assert faulted.fault.name
            state = await r.motion.fault_reset(node)
            assert state.state == "switch_on_disabled"
            assert state.last_transition == "fault reset (15)"
            assert state.fault is None
            assert not state.controlword & 0x0080


async def test_blocked_names_nmt_stopped() -> None:
    async with motion_rig() as r:
        for node in NODES:
            await r.rig.registry.nmt(node, NmtCommandName.STOP)
            with pytest.raises(EnableBlockedError) as blocked:
                await r.motion.enable(node)
            assert blocked.value.reasons[0].code == "nmt_stopped"
            assert "Stopped" in blocked.value.reasons[0].message
            await r.rig.registry.nmt(node, NmtCommandName.START)
            assert (await r.motion.enable(node)).state == "operation_enabled"


async def test_blocked_names_the_fault_in_words() -> None:
    async with motion_rig() as r:
        for node in NODES:
            await r.write(node, SIM_INJECT_FAULT, 0, FOLLOWING_ERROR_FAULT[node])
            await r.until(node, lambda s: s.state == "fault", timeout=2, what="fault")
            with pytest.raises(EnableBlockedError) as blocked:
                await r.motion.move(node, MoveRequest(position_rev=0.1, velocity_rpm=60))
            codes = [reason.code for reason in blocked.value.reasons]
            assert codes[:2] == ["not_enabled", "fault"]
            fault = blocked.value.state.fault
            assert fault is not None
            assert fault.name
            assert fault.name in blocked.value.reasons[1].message


async def test_blocked_names_quick_stop_active() -> None:
    async with motion_rig() as r:
        for node in NODES:
            await to_start_state(r, node, "quick_stop_active")
            with pytest.raises(EnableBlockedError) as blocked:
                await r.motion.move(node, MoveRequest(position_rev=0.1, velocity_rpm=60))
            assert "quick_stop_active" in [reason.code for reason in blocked.value.reasons]


async def test_blocked_names_an_unsupported_mode() -> None:
    async with motion_rig() as r:
        for node in NODES:
            await r.motion.enable(node)
            # Velocity mode (2) is in none of the three drives' 6502h: MDi shows 6061h = 0,
            # Kinco and the CiA 402 controller refuse the write (06090030h)
            with pytest.raises(EnableBlockedError) as blocked:
                await r.motion.set_mode(node, "vl")
            assert blocked.value.reasons[0].code == "mode_unsupported", node
            assert "vl" not in blocked.value.state.supported_modes
