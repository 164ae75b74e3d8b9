"""Node scan against the simulated drives: SDO sweep, boot-ups heard, vanished nodes."""

from __future__ import annotations

import pytest

from servodesk.bus.connection import BusManager
from servodesk.errors import BusNotConnectedError
from servodesk.models.bus import BusConfig
from servodesk.models.network import NmtCommandName
from servodesk.models.nodes import NmtStateName
from servodesk.nodes.registry import NodeRegistry
from servodesk_sim.drive import create_drive
from servodesk_sim.runner import SimNode
from tests.backend.network_rig import eventually, fast_settings, sim_rig


@pytest.mark.anyio
async def test_sweep_finds_every_drive_quickly() -> None:
    async with sim_rig() as rig:
        result = await rig.registry.scan(sdo_sweep=True, timeout_ms=50)
        assert [n.node for n in result.nodes] == [1, 2, 3]
        assert 50 <= result.duration_ms < 5000
        # a second scan re-identifies the known nodes through their sessions
        again = await rig.registry.scan(sdo_sweep=True, timeout_ms=50)
        assert [n.node for n in again.nodes] == [1, 2, 3]
        assert all(n.online for n in again.nodes)


@pytest.mark.anyio
async def test_scan_without_sweep_uses_the_boot_ups_heard() -> None:
    async with sim_rig(drives=()) as rig:
        assert (await rig.registry.scan(sdo_sweep=False, timeout_ms=50)).nodes == []
        rig.restart_drives(_drives())  # boot-ups while we listen
        await eventually(lambda: len(rig.registry.heard()) == 3, what="boot-ups")
        result = await rig.registry.scan(sdo_sweep=False, timeout_ms=50)
        assert [n.node for n in result.nodes] == [1, 2, 3]
        assert result.nodes[0].name == "DVS_CANOPEN"
        # a boot-up puts a node in Pre-operational
        assert {n.nmt_state for n in result.nodes} == {NmtStateName.PRE_OPERATIONAL}


@pytest.mark.anyio
async def test_vanished_nodes_stay_listed_offline() -> None:
    async with sim_rig() as rig:
        await rig.registry.scan(sdo_sweep=True, timeout_ms=50)
        rig.sim.stop()
        result = await rig.registry.scan(sdo_sweep=True, timeout_ms=50)
        assert [(n.node, n.online) for n in result.nodes] == [(1, False), (2, False), (3, False)]
        assert result.nodes[0].name == "DVS_CANOPEN"  # what we knew is kept


@pytest.mark.anyio
async def test_a_stopped_node_heard_by_its_heartbeat_is_listed() -> None:
    async with sim_rig() as rig:
        await rig.registry.add(3)
        await rig.registry.set_heartbeat(3, 50)
        await rig.registry.nmt(3, NmtCommandName.STOP)
        # A second tool instance on the same bus: node 3 does not answer SDO (Stopped) but
        # its heartbeat is heard.
        manager = BusManager(fast_settings())
        registry = NodeRegistry(manager, fast_settings())
        try:
            await manager.connect(BusConfig(interface="virtual", channel=rig.channel))
            await eventually(lambda: 3 in registry.heard(), what="heartbeat")
            result = await registry.scan(sdo_sweep=True, timeout_ms=50)
            by_node = {n.node: n for n in result.nodes}
            assert sorted(by_node) == [1, 2, 3]
            stopped = by_node[3]
            assert stopped.profile == "generic-cia301"  # identity unknown: no SDO
            assert stopped.vendor_id is None
            assert stopped.online
            assert stopped.nmt_state is NmtStateName.STOPPED
        finally:
            await registry.close()
            await manager.close()


@pytest.mark.anyio
async def test_scan_needs_a_bus() -> None:
    async with sim_rig(connect=False) as rig:
        with pytest.raises(BusNotConnectedError):
            await rig.registry.scan(sdo_sweep=True, timeout_ms=50)


def _drives() -> list[SimNode]:
    return [create_drive(1, "mdi-s1c"), create_drive(2, "kinco"), create_drive(3, "cia402")]
