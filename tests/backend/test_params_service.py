"""ParamService against the simulated drives: catalogue values, checked writes, when a change
takes effect, store / restore with confirmation."""

from __future__ import annotations

from dataclasses import replace

import pytest

from servodesk.errors import ConfirmationRequiredError, InvalidValueError
from servodesk.events.bus import EventKind, event
from servodesk.models.network import NmtCommandName
from servodesk.params.service import ParamService, resolve_value
from servodesk.sdo.service import SdoService
from servodesk_data import load
from tests.backend.sim_nodes import SdoTap, SimNodes

pytestmark = pytest.mark.anyio


async def test_list_reads_every_catalogue_parameter_from_the_drive(nodes: SimNodes) -> None:
    params = {p.name: p for p in await ParamService(nodes).list(1)}
    assert list(params) == [p.name for p in load("mdi-s1c").parameters]
    assert params["PA-14"].value == 4
    assert params["PA-14"].object == "2000:0F"
    assert (params["PA-14"].index, params["PA-14"].subindex) == (0x2000, 0x0F)
    assert params["PA-106"].value == 5
    assert params["PA-106"].choices["5"] == "500 kbit/s"
    assert params["PA-106"].takes_effect == "after_reset"
    assert params["PA-103"].unit == "rpm"
    assert all(p.error is None for p in params.values())


async def test_list_reports_a_refused_read_per_parameter(nodes: SimNodes) -> None:
    # A dictionary upload can leave the catalogue pointing at an object the drive lacks.
    service = ParamService(nodes)
    data = load("mdi-s1c")
    missing = replace(data.parameters[0], name="Missing", object=(0x5555, 0))
    nodes.drive_data["mdi-s1c"] = replace(data, parameters=(*data.parameters, missing))
    params = {p.name: p for p in await service.list(1)}
    assert params["Missing"].value is None
    assert params["Missing"].error == (
        "SDO abort 0x06020000: Object does not exist in the object dictionary"
    )
    assert params["PA-14"].value == 4


async def test_set_immediate_parameter_is_applied(nodes: SimNodes) -> None:
    result = await ParamService(nodes).set(1, "PA-103", 3000)
    assert result.message == "applied"
    assert (result.requires_reset, result.requires_store) == (False, False)
    assert result.param.value == 3000
    assert (await SdoService(nodes).read(1, 0x2006, 0x08)).value == 3000  # PA-103


async def test_set_pa14_to_can_bus(nodes: SimNodes) -> None:
    service = ParamService(nodes)
    await SdoService(nodes).write(1, 0x2000, 0x0F, 0)  # PA-14 away from CAN
    result = await service.set(1, "PA-14", 4)
    assert result.param.value == 4
    assert result.message == "applied"


async def test_set_bitrate_by_choice_label_needs_reset(nodes: SimNodes) -> None:
    result = await ParamService(nodes).set(1, "PA-106", "250 kbit/s")
    assert result.param.value == 4
    assert result.requires_reset is True
    assert result.requires_store is True
    # the bitrate has its own wizard, which also says how to bring the bus along
    assert result.message.startswith("written; the drive talks at the new bitrate after a store")
    assert "use Change bitrate…" in result.message
    assert result.param.pending is True
    # only written, not applied: the drive still answers at its old bitrate after this
    assert (await SdoService(nodes).read(1, 0x2006, 0x0B)).value == 4


@pytest.mark.parametrize(
    ("name", "value", "message"),
    [
        ("PA-106", 7, "allowed 0..6"),
        ("PA-106", "2 Mbit/s", "not one of 0 \\(20 kbit/s\\)"),
        ("PA-14", 5, "allowed 0..4"),
        ("Homing method", 19, "not an allowed setting; choose one of 17"),
        ("Following error window", -1, "allowed 0..4294967295 user units"),
        ("No such parameter", 1, "mdi-s1c has no parameter 'No such parameter'"),
    ],
)
async def test_invalid_values_are_refused_before_writing(
    nodes: SimNodes, name: str, value: int | str, message: str
) -> None:
    downloads = SdoTap(nodes, 1, writes_only=True)
    service = ParamService(nodes)
    with pytest.raises(InvalidValueError, match=message):
        await service.set(1, name, value)
    await service.get(1, "PA-14")  # answered: every earlier frame has reached the drive
    downloads.remove()
    assert downloads.frames == []


async def test_kinco_node_offset(nodes: SimNodes) -> None:
    service = ParamService(nodes)
    offset = await service.get(2, "Node offset")
    assert offset.value == 0
    assert offset.object == "2F80:00"
    assert (offset.min, offset.max) == (0, 127)
    result = await service.set(2, "Node offset", "0x05")
    assert result.param.value == 5
    assert result.requires_reset is True
    assert "use Change node ID…" in result.message  # the offset sets the node id


async def test_a_written_after_reset_parameter_is_pending_until_the_node_boots(
    nodes: SimNodes,
) -> None:
    service = ParamService(nodes)
    assert (await service.get(1, "PA-106")).pending is False
    await service.set(1, "PA-106", 5)  # the bitrate it has: the reset below changes nothing
    assert (await service.get(1, "PA-106")).pending is True
    assert [p.name for p in await service.list(1) if p.pending] == ["PA-106"]
    assert (await service.get(2, "Node offset")).pending is False  # another node
    service.on_node_event(event(EventKind.BOOT_UP, 1, "node 1 booted"))
    assert (await service.get(1, "PA-106")).pending is False


def test_resolve_value_accepts_labels_and_numbers() -> None:
    pa106 = load("mdi-s1c").parameter("PA-106")
    assert resolve_value(pa106, "1 Mbit/s") == 6
    assert resolve_value(pa106, " 500 KBIT/S ") == 5
    assert resolve_value(pa106, "3") == 3
    assert resolve_value(pa106, 0) == 0


async def test_store_and_restore_need_confirmation(nodes: SimNodes) -> None:
    downloads = SdoTap(nodes, 1, writes_only=True)
    service = ParamService(nodes)
    with pytest.raises(ConfirmationRequiredError):
        await service.store(1, confirm=False)
    with pytest.raises(ConfirmationRequiredError):
        await service.restore_defaults(1, confirm=False)
    await service.get(1, "PA-14")
    downloads.remove()
    assert downloads.frames == []


async def test_store_keeps_a_value_over_reset_and_restore_brings_defaults_back(
    nodes: SimNodes,
) -> None:
    service = ParamService(nodes)
    await service.set(1, "PA-103", 2500)
    stored = await service.store(1, confirm=True)
    assert "1010h" in stored.message
    await nodes.nmt(1, NmtCommandName.RESET_NODE)
    assert (await service.get(1, "PA-103")).value == 2500
    restored = await service.restore_defaults(1, confirm=True)
    assert "takes effect after reset" in restored.message
    assert (await service.get(1, "PA-103")).value == 2500  # not before the reset
    await nodes.nmt(1, NmtCommandName.RESET_NODE)
    assert (await service.get(1, "PA-103")).value == 6000


async def test_store_writes_the_save_signature(nodes: SimNodes) -> None:
    downloads = SdoTap(nodes, 3, writes_only=True)
    await ParamService(nodes).store(3, confirm=True)
    await ParamService(nodes).restore_defaults(3, confirm=True)
    await SdoService(nodes).read(3, 0x1000, 0)
    downloads.remove()
    assert [f.data.hex(" ").upper() for f in downloads.frames] == [
        "23 10 10 01 73 61 76 65",  # 1010h:01 = "save"
        "23 11 10 01 6C 6F 61 64",  # 1011h:01 = "load"
    ]


async def test_generic_node_has_no_parameters(nodes: SimNodes) -> None:
    nodes.generic_nodes.add(3)
    service = ParamService(nodes)
    assert await service.list(3) == []
    with pytest.raises(InvalidValueError, match="no parameter catalogue"):
        await service.set(3, "Homing method", 17)
