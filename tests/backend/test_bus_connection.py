"""BusManager against simulated drives on a virtual bus: connect, disconnect, reconnect,
simulated mode, counters, and a lost adapter that comes back."""

from __future__ import annotations

import asyncio

import can
import pytest
from can.interfaces import VALID_INTERFACES

from servodesk.bus.connection import BusManager
from servodesk.bus.interfaces import INTERFACES
from servodesk.errors import BusNotConnectedError, BusOpenError, InvalidValueError
from servodesk.models.bus import BusConfig, BusState, BusStatus
from servodesk.models.network import NmtCommandName
from servodesk.network.sync import SyncService
from tests.backend.network_rig import (
    Plug,
    eventually,
    fast_settings,
    new_channel,
    sim_rig,
    unpluggable_factory,
)


@pytest.mark.anyio
async def test_connect_disconnect_reconnect() -> None:
    async with sim_rig() as rig:
        seen: list[BusStatus] = []
        rig.bus.add_listener(seen.append)
        status = rig.bus.status()
        assert status.state is BusState.CONNECTED
        assert (status.interface, status.channel) == ("virtual", rig.channel)
        first_network = rig.bus.network
        await rig.registry.scan(sdo_sweep=True, timeout_ms=50)
        assert [n.node for n in rig.registry.all()] == [1, 2, 3]

        status = await rig.bus.disconnect()
        assert status.state is BusState.DISCONNECTED
        with pytest.raises(BusNotConnectedError):
            _ = rig.bus.network
        assert rig.registry.all() == []  # the registry clears itself on disconnect

        status = await rig.bus.reconnect()
        assert status.state is BusState.CONNECTED
        assert status.reconnects == 1
        assert rig.bus.network is not first_network
        await rig.registry.scan(sdo_sweep=True, timeout_ms=50)
        assert rig.registry.info(1).name == "DVS_CANOPEN"
        states = [s.state for s in seen]
        assert states == [BusState.DISCONNECTED, BusState.CONNECTING, BusState.CONNECTED]


@pytest.mark.anyio
async def test_counters_count_rx_tx_and_sync_frames() -> None:
    async with sim_rig() as rig:
        await rig.registry.scan(sdo_sweep=True, timeout_ms=50)
        after_scan = rig.bus.status()
        # 127 sweep requests plus the identification reads; the answers come back
        assert after_scan.tx_frames >= 127
        assert after_scan.rx_frames >= 3
        sync = SyncService(rig.bus)
        config = await sync.set(1000)
        assert config.producing
        assert config.period_us == 1000
        await eventually(
            lambda: rig.bus.status().tx_frames >= after_scan.tx_frames + 20, what="SYNC frames"
        )
        assert (await sync.set(None)).producing is False
        with pytest.raises(InvalidValueError):
            await sync.set(10)
        sync.close()


@pytest.mark.anyio
async def test_connect_failure_is_reported_and_not_retried() -> None:
    calls: list[BusConfig] = []

    def broken(config: BusConfig) -> can.BusABC:
        calls.append(config)
        raise can.CanInterfaceNotImplementedError("driver library not found")

    manager = BusManager(fast_settings(), bus_factory=broken)
    status = await manager.connect(BusConfig(interface="pcan", channel="PCAN_USBBUS1"))
    assert status.state is BusState.ERROR
    assert status.error is not None
    assert "driver library not found" in status.error
    await asyncio.sleep(0.2)  # longer than the reconnect delay: no automatic retry
    assert len(calls) == 1
    assert manager.status().state is BusState.ERROR
    await manager.close()


@pytest.mark.anyio
async def test_an_adapter_that_does_not_open_leaves_the_working_bus_connected() -> None:
    async with sim_rig() as rig:
        await rig.registry.scan(sdo_sweep=True, timeout_ms=50)
        network = rig.bus.network
        with pytest.raises(BusOpenError) as refused:
            await rig.bus.connect(BusConfig(interface="socketcan", channel="nope0"))
        assert str(refused.value).startswith("could not open socketcan nope0 (")
        assert str(refused.value).endswith(
            f"virtual {rig.channel} stays connected; check the interface and channel"
        )
        status = rig.bus.status()
        assert (status.state, status.channel) == (BusState.CONNECTED, rig.channel)
        assert rig.bus.network is network  # not even re-opened
        assert rig.registry.info(1).name == "DVS_CANOPEN"
        assert (await rig.registry.heartbeat(1)) >= 0  # the drives still answer
        # another adapter that opens replaces the bus as before
        other = new_channel()
        status = await rig.bus.connect(BusConfig(interface="virtual", channel=other))
        assert (status.state, status.channel) == (BusState.CONNECTED, other)


@pytest.mark.anyio
async def test_simulated_mode_runs_three_drives() -> None:
    manager = BusManager(fast_settings())
    try:
        status = await manager.connect(BusConfig(simulated=True))
        assert status.state is BusState.CONNECTED
        assert status.simulated
        assert status.channel is not None
        assert status.channel.startswith("servodesk-sim-")
        sim = manager.sim
        assert sim is not None
        assert sim.running
        assert sorted(node.node_id for node in sim.nodes) == [1, 2, 3]

        # reconnect re-opens only the tool's side: the drives keep running
        status = await manager.reconnect()
        assert status.state is BusState.CONNECTED
        assert manager.sim is sim

        # a new connect replaces everything, the old drives stop
        await manager.connect(BusConfig(simulated=True))
        assert manager.sim is not sim
        assert not sim.running
    finally:
        await manager.close()
    assert manager.sim is None


@pytest.mark.anyio
async def test_lost_adapter_goes_to_error_and_recovers() -> None:
    plug = Plug()
    async with sim_rig(bus_factory=unpluggable_factory(plug)) as rig:
        await rig.registry.scan(sdo_sweep=True, timeout_ms=50)
        network_before = rig.bus.network

        plug.pulled.set()
        await eventually(lambda: rig.bus.status().state is BusState.ERROR, what="ERROR state")
        status = rig.bus.status()
        assert status.error is not None
        assert "unplugged" in status.error
        assert status.bus_errors >= 1
        with pytest.raises(BusNotConnectedError):
            rig.registry.session(1)
        # the reconnect task keeps trying while the adapter is missing
        await eventually(
            lambda: "reconnecting failed" in (rig.bus.status().error or ""), what="retries"
        )

        plug.pulled.clear()
        await eventually(lambda: rig.bus.status().state is BusState.CONNECTED, what="recovery")
        assert rig.bus.status().reconnects == 1
        assert rig.bus.network is not network_before
        # the registry kept its nodes and reaches them through the new connection
        assert [n.node for n in rig.registry.all()] == [1, 2, 3]
        assert await rig.registry.session(1).upload(0x1008, 0) == b"DVS_CANOPEN"
        kinds = [(e.kind, e.message.split(":")[0]) for e in rig.events_of("bus")]
        assert ("bus", "bus error") in kinds
        assert rig.events_of("bus")[-1].message.startswith("bus connected")


@pytest.mark.anyio
async def test_failing_send_goes_to_error() -> None:
    plug = Plug()
    async with sim_rig(bus_factory=unpluggable_factory(plug)) as rig:
        await rig.registry.add(1)
        # only the send path fails: the notifier is between two receives
        plug.pulled.set()
        with pytest.raises(BusNotConnectedError):
            await rig.registry.nmt(1, NmtCommandName.START)
        await eventually(lambda: rig.bus.status().state is BusState.ERROR, what="ERROR state")
        plug.pulled.clear()
        await eventually(lambda: rig.bus.status().state is BusState.CONNECTED, what="recovery")


@pytest.mark.anyio
async def test_disconnect_while_reconnecting_stops_retrying() -> None:
    plug = Plug()
    async with sim_rig(bus_factory=unpluggable_factory(plug)) as rig:
        plug.pulled.set()
        await eventually(lambda: rig.bus.status().state is BusState.ERROR, what="ERROR state")
        status = await rig.bus.disconnect()
        assert status.state is BusState.DISCONNECTED
        opened = plug.opened
        plug.pulled.clear()
        await asyncio.sleep(0.4)  # two retry periods: nobody may reconnect behind our back
        assert rig.bus.status().state is BusState.DISCONNECTED
        assert plug.opened == opened


def test_interfaces_list_the_common_ones_first_and_every_python_can_interface() -> None:
    names = [info.name for info in INTERFACES]
    assert names[:6] == ["socketcan", "pcan", "kvaser", "slcan", "socketcand", "virtual"]
    assert set(VALID_INTERFACES) - {"udp_multicast"} <= set(names)  # it sends to the LAN
    assert "udp_multicast" not in names
    assert len(names) == len(set(names))
    socketcan = INTERFACES[0]
    assert socketcan.label == "SocketCAN (Linux)"
    assert socketcan.example_channel == "can0"


def test_new_channel_names_are_unique() -> None:
    assert new_channel() != new_channel()
