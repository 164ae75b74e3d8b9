"""The controller lease and the heartbeat-consumer protection, on the simulated drives."""

from __future__ import annotations

import asyncio

import can
import pytest

from servodesk.errors import InvalidValueError
from servodesk.models.bus import BusState
from servodesk.models.safety import JogRequest
from servodesk.motion.lease import Client, HeldByOtherError
from tests.backend.motion_rig import CIA402, KINCO, MDI
from tests.backend.network_rig import Plug, eventually, unpluggable_factory
from tests.backend.safety_rig import PAGE, SafetyRig, safety_rig

pytestmark = pytest.mark.anyio

CONSUMER = 0x1016
OTHER = Client(id="page-b", name="Bob")
SCRIPT = Client.anonymous_one()


async def consumer_entries(rig: SafetyRig, node: int) -> list[int]:
    count = await rig.read(node, CONSUMER, 0, signed=False)
    return [await rig.read(node, CONSUMER, sub, signed=False) for sub in range(1, count + 1)]


async def test_a_second_client_is_refused_until_it_takes_over() -> None:
    async with safety_rig() as rig:
        await rig.safety.authorize(CIA402, PAGE)  # acting on a free node takes it
        assert rig.safety.controller(CIA402, PAGE).you
        with pytest.raises(HeldByOtherError) as refused:
            await rig.safety.authorize(CIA402, OTHER)
        assert refused.value.holder.name == "Alice"
        with pytest.raises(HeldByOtherError):
            await rig.safety.authorize(CIA402, SCRIPT)  # scripts too
        with pytest.raises(HeldByOtherError):
            await rig.safety.take(CIA402, OTHER, take_over=False)
        info = await rig.safety.take(CIA402, OTHER, take_over=True)
        assert info.you
        assert info.holder is not None
        assert info.holder.client_id == "page-b"
        with pytest.raises(HeldByOtherError):
            await rig.safety.authorize(CIA402, PAGE)


async def test_take_over_stops_the_previous_holders_jog() -> None:
    async with safety_rig() as rig:
        jog = await rig.jog(KINCO)
        await rig.safety.take(KINCO, OTHER, take_over=True)
        info, state = await rig.stopped(jog)
        assert info.stop_reason == "control taken over by Bob"
        assert state.velocity_rpm == 0


async def test_anonymous_scripts_act_on_free_nodes_without_holding_them() -> None:
    async with safety_rig() as rig:
        await rig.safety.authorize(MDI, SCRIPT)
        assert rig.safety.lease.holder(MDI) is None
        with pytest.raises(InvalidValueError):
            await rig.safety.take(MDI, SCRIPT, take_over=False)


async def test_quick_stop_is_open_to_everyone() -> None:
    async with safety_rig() as rig:
        jog = await rig.jog(CIA402)
        state = await rig.safety.quick_stop(CIA402)  # no client at all: never refused
        assert rig.safety.jogs.get(jog.jog_id).stop_reason == "quick stop"
        assert state.state in ("quick_stop_active", "switch_on_disabled")
        result = await rig.safety.quick_stop_all()
        assert sorted(result.stopped) == [MDI, KINCO, CIA402]


async def test_heartbeat_consumer_is_configured_and_undone() -> None:
    async with safety_rig() as rig:
        before = await consumer_entries(rig, CIA402)
        info = await rig.safety.take(CIA402, PAGE, take_over=False)
        assert info.protection.active
        tool, ms = info.protection.tool_node_id, info.protection.consumer_ms
        assert (tool << 16) | ms in await consumer_entries(rig, CIA402)
        released = await rig.safety.release(CIA402, PAGE)
        assert released.holder is None
        assert not released.protection.active
        assert await consumer_entries(rig, CIA402) == before


async def test_the_drive_stops_by_itself_when_the_tool_falls_silent() -> None:
    """The adapter is pulled mid-jog: the tool can send neither a stop nor its heartbeat, so
    the drive's heartbeat consumer is what stops the axis."""
    plug = Plug()
    async with safety_rig(bus_factory=unpluggable_factory(plug)) as rig:
        await rig.jog(CIA402)
        assert rig.safety.controller(CIA402, PAGE).protection.active
        listener = can.Bus(interface="virtual", channel=rig.rig.channel)  # an independent ear
        try:
            plug.pulled.set()
            emcy = await asyncio.to_thread(wait_for_frame, listener, 0x80 + CIA402)
        finally:
            listener.shutdown()
        assert emcy.data[:2] != b"\x00\x00"  # the drive's heartbeat-consumer fault
        plug.pulled.clear()
        await eventually(lambda: rig.rig.bus.status().state is BusState.CONNECTED, what="back")
        state = await rig.until(CIA402, lambda s: s.velocity_rpm == 0, timeout=5, what="stop")
        assert state.fault is not None


def wait_for_frame(bus: can.BusABC, can_id: int) -> can.Message:
    for _ in range(10_000):
        msg = bus.recv(timeout=5)
        if msg is None:
            break
        if msg.arbitration_id == can_id:
            return msg
    raise AssertionError(f"no frame {can_id:03X}h")


async def test_a_jog_needs_its_own_value() -> None:
    async with safety_rig() as rig:
        with pytest.raises(InvalidValueError):
            await rig.safety.start_jog(CIA402, JogRequest(mode="pv", torque_pct=5), PAGE)
