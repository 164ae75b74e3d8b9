"""Every trigger stops a running PV jog on a simulated drive: the jog says why, and the axis
comes to a standstill (asserted on the drive's own state, never on time)."""

from __future__ import annotations

import pytest

from servodesk.models.bus import BusState
from servodesk.motion.jog import JogStoppedError
from tests.backend.motion_rig import CIA402, KINCO, MDI, SIM_INJECT_FAULT
from tests.backend.network_rig import Plug, eventually, unpluggable_factory
from tests.backend.safety_rig import HALT, PAGE, safety_rig

pytestmark = pytest.mark.anyio

PRODUCER_HEARTBEAT = 0x1017


async def test_missed_keepalive_halts_the_axis() -> None:
    async with safety_rig() as rig:
        jog = await rig.jog(CIA402, keepalive_ms=100)
        info, state = await rig.stopped(jog)
        assert info.stop_reason is not None
        assert info.stop_reason.startswith("keep-alive missed")
        assert state.state == "operation_enabled"  # halted, not disabled: jog again at once
        assert state.controlword & HALT
        with pytest.raises(JogStoppedError):
            rig.keep(jog)  # re-arming is explicit


async def test_keepalives_keep_it_moving_until_the_socket_closes() -> None:
    async with safety_rig() as rig:
        rig.safety.socket_opened(PAGE.id)
        jog = await rig.jog(KINCO)
        for _ in range(5):
            rig.keep(jog)
            state = await rig.motion.state(KINCO)
        assert rig.safety.jogs.get(jog.jog_id).state == "running"
        assert state.velocity_rpm > 0
        rig.safety.socket_closed(PAGE.id)
        info, state = await rig.stopped(jog)
        assert info.stop_reason == "the page's connection closed"
        assert state.controlword & HALT


async def test_page_hidden_stops_the_jog() -> None:
    async with safety_rig() as rig:
        jog = await rig.jog(MDI)
        rig.safety.page_hidden(PAGE.id)
        info, _ = await rig.stopped(jog)
        assert info.stop_reason == "the page was hidden"


async def test_heartbeat_lost_stops_the_jog() -> None:
    async with safety_rig() as rig:
        await rig.rig.registry.set_heartbeat(CIA402, 100)
        jog = await rig.jog(CIA402)
        rig.keep(jog)
        # the drive falls silent behind the monitor's back (a raw write, not through the
        # registry, which would tell the monitor to expect no heartbeat)
        session = rig.rig.registry.session(CIA402)
        await session.run(
            lambda r: r.sdo.download(PRODUCER_HEARTBEAT, 0, b"\x00\x00"), what="write 1017h"
        )
        while rig.safety.jogs.get(jog.jog_id).state == "running":
            rig.keep(jog)  # the page is still there: only the lost heartbeat may stop it
            await rig.motion.state(CIA402)
        info, state = await rig.stopped(jog)
        assert info.stop_reason == "heartbeat lost"
        assert state.controlword & HALT


async def test_emcy_from_the_node_stops_the_jog() -> None:
    async with safety_rig() as rig:
        jog = await rig.jog(KINCO)
        await rig.write(KINCO, SIM_INJECT_FAULT, 0, 0x8611)  # following error: sends an EMCY
        info, _state = await rig.stopped(jog)
        assert info.stop_reason is not None
        assert info.stop_reason.startswith("EMCY")


async def test_bus_error_stops_the_jog_and_the_stop_is_sent_when_it_is_back() -> None:
    plug = Plug()
    async with safety_rig(bus_factory=unpluggable_factory(plug)) as rig:
        jog = await rig.jog(CIA402)
        plug.pulled.set()
        await eventually(lambda: rig.rig.bus.status().state is BusState.ERROR, what="bus error")
        await eventually(lambda: rig.safety.jogs.get(jog.jog_id).state == "stopped", what="stop")
        await rig.safety.jogs.settled()
        assert CIA402 in rig.safety.jogs.unsent  # nothing could be sent meanwhile
        plug.pulled.clear()
        await eventually(lambda: rig.rig.bus.status().state is BusState.CONNECTED, what="back")
        await eventually(lambda: not rig.safety.jogs.unsent, what="stop sent again")
        info, state = await rig.stopped(jog)
        assert info.stop_reason is not None
        assert info.stop_reason.startswith("bus error")
        assert state.velocity_rpm == 0
