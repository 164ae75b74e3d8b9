"""NodeRegistry against the simulated drives: identification and profiles, NMT, heartbeat,
dictionaries, node-id moves, and a device no profile knows (python-canopen's own LocalNode)."""

from __future__ import annotations

import asyncio
from collections.abc import Iterator
from contextlib import contextmanager

import can
import canopen
import pytest
from canopen.objectdictionary import ODRecord, ODVariable

from servodesk.errors import (
    CommTimeoutError,
    InvalidValueError,
    NodeNotFoundError,
    NodeStoppedError,
)
from servodesk.models.network import NmtCommandName
from servodesk.models.nodes import NmtStateName
from servodesk.od import load_od
from servodesk_data import eds_path
from servodesk_sim.frames import Frame
from tests.backend.network_rig import eventually, sim_rig

UNSIGNED8 = 0x0005
UNSIGNED32 = 0x0007
SAVE = b"save"  # 1010h:01 signature (CiA 301 §7.5.2.13)


@pytest.mark.anyio
async def test_scan_identifies_the_three_drives() -> None:
    async with sim_rig() as rig:
        result = await rig.registry.scan(sdo_sweep=True, timeout_ms=50)
        by_node = {info.node: info for info in result.nodes}
        assert sorted(by_node) == [1, 2, 3]
        assert [by_node[n].profile for n in (1, 2, 3)] == ["mdi-s1c", "kinco", "cia402"]
        assert by_node[1].name == "DVS_CANOPEN"
        assert by_node[1].vendor_id == 0x00445653  # "DVS"
        assert by_node[1].device_type == 0
        assert by_node[3].device_type == 0x00020192
        assert all(info.online for info in result.nodes)
        assert by_node[2].od_filename == "kinco/drive.eds"
        assert rig.registry.profile_data(1) is not None
        assert rig.registry.od(3).get(0x6041) is not None  # Statusword


@pytest.mark.anyio
async def test_unknown_node_is_not_found() -> None:
    async with sim_rig() as rig:
        with pytest.raises(NodeNotFoundError):
            rig.registry.session(9)
        with pytest.raises(CommTimeoutError):
            await rig.registry.add(9)  # nobody there
        with pytest.raises(InvalidValueError):
            await rig.registry.add(128)
        assert rig.registry.all() == []


@pytest.mark.anyio
async def test_nmt_stop_and_start_reach_the_drive() -> None:
    async with sim_rig() as rig:
        await rig.registry.add(1)
        info = await rig.registry.nmt(1, NmtCommandName.STOP)
        assert info.nmt_state is NmtStateName.STOPPED
        # a Stopped drive does not answer SDO (MDi-S1-C manual table 2.8): said at once
        with pytest.raises(NodeStoppedError, match="node 1 is Stopped"):
            await rig.registry.session(1).upload(0x1000, 0)  # Device type
        # ... and being stopped by us, it is not declared lost for it
        await asyncio.sleep(0.3)  # longer than one monitor tick
        assert rig.registry.info(1).online
        assert not rig.events_of("node-lost")

        info = await rig.registry.nmt(1, NmtCommandName.START)
        assert info.nmt_state is NmtStateName.OPERATIONAL
        assert await rig.registry.session(1).upload(0x1008, 0) == b"DVS_CANOPEN"
        assert [e.message for e in rig.events_of("nmt", 1)] == [
            "NMT stop sent to node 1",
            "NMT start sent to node 1",
        ]


@pytest.mark.anyio
async def test_heartbeat_corrects_the_commanded_state() -> None:
    async with sim_rig() as rig:
        await rig.registry.scan(sdo_sweep=True, timeout_ms=50)
        await rig.registry.nmt_broadcast(NmtCommandName.START)
        assert {i.nmt_state for i in rig.registry.all()} == {NmtStateName.OPERATIONAL}
        assert await rig.registry.set_heartbeat(2, 50) == 50
        assert await rig.registry.heartbeat(2) == 50
        # another master puts node 2 back into Pre-operational behind the tool's back: its
        # heartbeat says so, and that overrides what the tool last commanded
        rig.sim.inject(Frame(0x000, bytes([0x80, 2])))  # NMT enter Pre-operational, node 2
        await eventually(
            lambda: rig.registry.info(2).nmt_state is NmtStateName.PRE_OPERATIONAL,
            what="the heartbeat's state",
        )
        # node 1 sends no heartbeat: it stays in the commanded state
        assert rig.registry.info(1).nmt_state is NmtStateName.OPERATIONAL
        with pytest.raises(InvalidValueError):
            await rig.registry.set_heartbeat(2, 70000)


@pytest.mark.anyio
async def test_reset_node_boots_and_wait_boot_sees_it() -> None:
    async with sim_rig() as rig:
        await rig.registry.add(3)
        waiter = asyncio.create_task(rig.registry.wait_boot(3, 2.0))
        await asyncio.sleep(0)  # the waiter registers before the reset goes out
        info = await rig.registry.nmt(3, NmtCommandName.RESET_NODE)
        assert info.nmt_state in (NmtStateName.INITIALISING, NmtStateName.PRE_OPERATIONAL)
        assert await waiter
        assert rig.registry.info(3).nmt_state is NmtStateName.PRE_OPERATIONAL  # from boot-up
        assert rig.events_of("boot-up", 3)
        # no reset, no boot-up
        assert not await rig.registry.wait_boot(3, 0.1)


@pytest.mark.anyio
async def test_uploaded_dictionary_replaces_and_resets() -> None:
    async with sim_rig() as rig:
        await rig.registry.add(1)
        uploaded = load_od(eds_path("cia402"), node_id=1)
        info = await rig.registry.set_od(1, uploaded, "upload")
        assert (info.od_source, info.od_filename) == ("upload", "drive.eds")
        assert rig.registry.od(1) is uploaded
        # the new session works with the new dictionary
        assert await rig.registry.session(1).upload(0x1008, 0) == b"DVS_CANOPEN"
        # a rescan of the same device keeps the user's dictionary
        await rig.registry.add(1)
        assert rig.registry.info(1).od_source == "upload"
        info = await rig.registry.reset_od(1)
        assert (info.od_source, info.od_filename) == ("profile", "mdi-s1c/drive.eds")
        assert rig.registry.od(1) is not uploaded


@pytest.mark.anyio
async def test_node_id_change_then_move() -> None:
    async with sim_rig() as rig:
        registry = rig.registry
        await registry.add(1)
        session = registry.session(1)

        def set_pa105(remote: canopen.RemoteNode) -> None:
            remote.sdo[0x2006][0x0A].raw = 9  # PA-105 node id (seed 000 §2.2)
            remote.sdo.download(0x1010, 1, SAVE)  # Store parameters: all

        await session.run(set_pa105, what="write PA-105")
        booted = asyncio.create_task(registry.wait_boot(9, 2.0))
        await asyncio.sleep(0)
        await registry.nmt(1, NmtCommandName.RESET_NODE)
        assert await booted

        info = await registry.move(1, 9)
        assert info.node == 9
        assert info.profile == "mdi-s1c"
        assert [n.node for n in registry.all()] == [9]
        assert await registry.session(9).upload(0x1008, 0) == b"DVS_CANOPEN"
        # the dictionary was resolved for the new id: TPDO1 COB-ID = 180h + 9
        cob_id = registry.od(9).get(0x1800, 1)  # TPDO1 communication parameter: COB-ID
        assert cob_id is not None
        assert isinstance(cob_id.default, int)
        assert cob_id.default & 0x7FF == 0x189
        with pytest.raises(NodeNotFoundError):
            registry.info(1)


def _unknown_device_od(device_type: int) -> canopen.ObjectDictionary:
    """A device no profile knows: 1000h and 1018h only (no 1008h name)."""
    od = canopen.ObjectDictionary()  # type: ignore[no-untyped-call]

    def var(name: str, index: int, sub: int, data_type: int, value: int) -> ODVariable:
        variable = ODVariable(name, index, sub)
        variable.data_type = data_type
        variable.access_type = "ro"
        variable.default = value
        return variable

    od.add_object(var("Device type", 0x1000, 0, UNSIGNED32, device_type))
    identity = ODRecord("Identity object", 0x1018)
    identity.add_member(var("Highest sub-index", 0x1018, 0, UNSIGNED8, 4))
    for sub, value in ((1, 0x00ABCDEF), (2, 0x42), (3, 7), (4, 1234)):
        identity.add_member(var(f"sub {sub}", 0x1018, sub, UNSIGNED32, value))
    od.add_object(identity)
    return od


@contextmanager
def local_device(channel: str, node: int, device_type: int) -> Iterator[None]:
    """python-canopen's own SDO server as an unknown device on the channel."""
    network = canopen.Network(can.Bus(interface="virtual", channel=channel))
    network.connect()
    network.create_node(node, _unknown_device_od(device_type))
    try:
        yield
    finally:
        network.disconnect()


@pytest.mark.anyio
@pytest.mark.parametrize(
    ("device_type", "profile", "has_6041"),
    [
        (0x00000191, "generic-cia301", False),  # a CiA 401 I/O module
        (0x00020192, "generic-cia402", True),  # an unknown CiA 402 drive
    ],
)
async def test_identity_of_an_unknown_device(
    device_type: int, profile: str, has_6041: bool
) -> None:
    async with sim_rig(drives=()) as rig:
        with local_device(rig.channel, 5, device_type):
            result = await rig.registry.scan(sdo_sweep=True, timeout_ms=50)
            assert [n.node for n in result.nodes] == [5]
            info = result.nodes[0]
            assert info.device_type == device_type
            assert (info.vendor_id, info.product_code) == (0x00ABCDEF, 0x42)
            assert (info.revision, info.serial) == (7, 1234)
            assert info.name is None  # it has no 1008h
            assert info.profile == profile
            assert rig.registry.profile_data(5) is None
            model = rig.registry.od(5)
            assert (model.get(0x6041) is not None) == has_6041  # Statusword
            assert model.get(0x1018, 1) is not None
