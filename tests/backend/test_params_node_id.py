"""Guided node-id and bitrate changes against the simulated drives."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from servodesk.errors import (
    CommTimeoutError,
    ConfirmationRequiredError,
    InvalidValueError,
    NodeNotFoundError,
)
from servodesk.params.node_id import NodeIdService
from servodesk.sdo.service import SdoService
from servodesk.settings import Settings
from servodesk_sim.drive import SimDrive
from tests.backend.sim_nodes import SdoTap, SimNodes

pytestmark = pytest.mark.anyio


@pytest.fixture
def nodes() -> Iterator[SimNodes]:
    with SimNodes(sdo_timeout=0.1) as access:
        yield access


@pytest.fixture
def service(nodes: SimNodes) -> NodeIdService:
    return NodeIdService(nodes, Settings(boot_wait=2.0))


def drive(nodes: SimNodes, profile: str) -> SimDrive:
    for node in nodes.sim.nodes:
        if isinstance(node, SimDrive) and node.profile == profile:
            return node
    raise LookupError(profile)


async def settle(nodes: SimNodes) -> None:
    """One answered request: every frame sent before it has reached the drives."""
    await SdoService(nodes).read(3, 0x1000, 0)  # Device type


async def test_mdi_node_id_change_moves_the_drive(nodes: SimNodes, service: NodeIdService) -> None:
    result = await service.change_node_id(1, 9, confirm=True)
    assert (result.old_node, result.new_node) == (1, 9)
    assert result.node.node == 9
    assert result.steps == [
        "Wrote PA-105 (2006:0A) = 9",
        'Stored the parameters (1010h:01 = "save")',
        "Reset node 1 (NMT reset node)",
        "Node 9 booted (boot-up message 709h)",
        "ServoDesk now talks to the drive as node 9",
    ]
    assert drive(nodes, "mdi-s1c").node_id == 9
    sdo = SdoService(nodes)
    assert (await sdo.read(9, 0x1008, 0)).value == "DVS_CANOPEN"  # Manufacturer device name
    assert (await sdo.read(9, 0x2006, 0x0A)).value == 9  # PA-105
    with pytest.raises(NodeNotFoundError):
        await sdo.read(1, 0x1000, 0)


async def test_kinco_node_id_is_dip_switch_plus_offset(
    nodes: SimNodes, service: NodeIdService
) -> None:
    result = await service.change_node_id(2, 9, confirm=True)
    assert result.steps[0] == "Wrote Node offset (2F80:00) = 7: DIP switch 2 + offset 7 = node 9"
    assert drive(nodes, "kinco").node_id == 9
    assert (await SdoService(nodes).read(9, 0x2F80, 0)).value == 7  # Node_Offset
    # and on from there: the DIP switch still gives 2
    again = await service.change_node_id(9, 20, confirm=True)
    assert again.steps[0] == "Wrote Node offset (2F80:00) = 18: DIP switch 2 + offset 18 = node 20"
    assert drive(nodes, "kinco").node_id == 20


async def test_kinco_id_below_the_dip_switch_needs_the_switch() -> None:
    with SimNodes([(2, "kinco")]) as kinco_only:
        service = NodeIdService(kinco_only, Settings(boot_wait=2.0))
        downloads = SdoTap(kinco_only, writes_only=True)
        with pytest.raises(InvalidValueError, match="Change the DIP switch to reach node 1") as no:
            await service.change_node_id(2, 1, confirm=True)
        assert "the DIP switch gives 2" in str(no.value)
        await SdoService(kinco_only).read(2, 0x1000, 0)  # answered: earlier frames arrived
        downloads.remove()
        assert downloads.frames == []
        assert drive(kinco_only, "kinco").node_id == 2


@pytest.mark.parametrize(
    ("node", "new", "error", "message"),
    [
        (1, 3, InvalidValueError, "node 3 is already in use on the bus"),
        (1, 1, InvalidValueError, "already is node 1"),
        (1, 128, InvalidValueError, "outside 1..127"),
        (3, 9, InvalidValueError, "cia402\\) has no node-id parameter"),
        (1, 9, ConfirmationRequiredError, "confirm"),
    ],
)
async def test_node_id_change_refused_before_anything_is_written(
    nodes: SimNodes,
    service: NodeIdService,
    node: int,
    new: int,
    error: type[Exception],
    message: str,
) -> None:
    downloads = SdoTap(nodes, writes_only=True)
    with pytest.raises(error, match=message):
        await service.change_node_id(node, new, confirm=error is not ConfirmationRequiredError)
    await settle(nodes)
    downloads.remove()
    assert downloads.frames == []
    assert sorted(d.node_id for d in nodes.sim.nodes) == [1, 2, 3]


async def test_bitrate_change_leaves_the_drive_silent_at_the_old_bitrate(
    nodes: SimNodes, service: NodeIdService
) -> None:
    result = await service.change_bitrate(1, 250_000, confirm=True)
    assert result.bitrate == 250_000
    assert result.reconnect_required is True
    assert result.steps == [
        "Wrote PA-106 (2006:0B) = 4 (0x04)",
        'Stored the parameters (1010h:01 = "save")',
        "Reset node 1 (NMT reset node)",
        "The drive now talks at 250 kbit/s only: reconnect the bus at 250 kbit/s",
    ]
    await settle(nodes)  # the reset has reached the drive
    assert drive(nodes, "mdi-s1c").silent
    with pytest.raises(CommTimeoutError):
        await SdoService(nodes).read(1, 0x1000, 0)
    assert (await SdoService(nodes).read(2, 0x1000, 0)).value == 0x00020192  # others go on


async def test_kinco_bitrate_is_a_register_pair(nodes: SimNodes, service: NodeIdService) -> None:
    result = await service.change_bitrate(2, 500_000, confirm=True)
    assert result.steps[:2] == [
        "Wrote Bitrate register 1 (2F81:00) = 0 (0x00)",
        "Wrote Bitrate register 2 (2F82:00) = 28 (0x1C)",
    ]
    assert result.steps[-1].endswith("reconnect the bus at 500 kbit/s")
    await settle(nodes)  # the reset has reached the drive
    assert drive(nodes, "kinco").silent


@pytest.mark.parametrize(
    ("node", "bitrate", "error", "message"),
    [
        (1, 800_000, InvalidValueError, "supported: 20000, 50000, 100000, 125000, 250000"),
        (3, 500_000, InvalidValueError, "cia402 sets its bitrate outside CANopen"),
        (1, 250_000, ConfirmationRequiredError, "confirm"),
    ],
)
async def test_bitrate_change_refused_before_anything_is_written(
    nodes: SimNodes,
    service: NodeIdService,
    node: int,
    bitrate: int,
    error: type[Exception],
    message: str,
) -> None:
    downloads = SdoTap(nodes, writes_only=True)
    with pytest.raises(error, match=message):
        await service.change_bitrate(node, bitrate, confirm=error is not ConfirmationRequiredError)
    await settle(nodes)
    downloads.remove()
    assert downloads.frames == []
    assert not any(d.silent for d in nodes.sim.nodes if isinstance(d, SimDrive))


async def test_generic_nodes_cannot_be_readdressed(nodes: SimNodes, service: NodeIdService) -> None:
    nodes.generic_nodes.add(1)
    with pytest.raises(InvalidValueError, match="generic profile"):
        await service.change_node_id(1, 9, confirm=True)
    with pytest.raises(InvalidValueError, match="generic profile"):
        await service.change_bitrate(1, 250_000, confirm=True)
