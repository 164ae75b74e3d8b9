"""SdoService against the simulated drives: typed reads and writes, refusals before any frame,
abort codes with their meaning."""

from __future__ import annotations

import pytest

from servodesk.errors import InvalidValueError, NodeNotFoundError, SdoAbortError
from servodesk.sdo.service import SdoService
from tests.backend.sim_nodes import SdoTap, SimNodes

pytestmark = pytest.mark.anyio

UPLOAD_REQUEST = 0x40  # SDO initiate upload command


async def test_read_manufacturer_device_name(nodes: SimNodes) -> None:
    value = await SdoService(nodes).read(1, 0x1008, 0)  # Manufacturer device name
    assert value.value == "DVS_CANOPEN"
    assert value.text == "DVS_CANOPEN"
    assert value.name == "Manufacturer device name"
    assert value.data_type_name == "VISIBLE_STRING"
    assert value.raw_hex == "44 56 53 5F 43 41 4E 4F 50 45 4E"


async def test_read_integer_shows_hex_and_decimal(nodes: SimNodes) -> None:
    value = await SdoService(nodes).read(2, 0x1018, 1)  # Identity object: vendor-ID
    assert value.value == 0x300
    assert value.text == "0x00000300 (768)"
    assert value.raw_hex == "00 03 00 00"
    assert value.name == "Identity object: Vendor-ID"


async def test_write_hex_string_and_read_back(nodes: SimNodes) -> None:
    sdo = SdoService(nodes)
    written = await sdo.write(1, 0x6065, 0, "0x1F4")  # Following error window
    assert written.value == 500
    assert (await sdo.read(1, 0x6065, 0)).raw_hex == "F4 01 00 00"


async def test_write_signed_value(nodes: SimNodes) -> None:
    sdo = SdoService(nodes)
    written = await sdo.write(3, 0x607A, 0, -1000)  # Target position, INTEGER32
    assert written.value == -1000
    assert written.raw_hex == "18 FC FF FF"
    assert written.text == "0xFFFFFC18 (-1000)"
    assert (await sdo.write(3, 0x607A, 0, "-5")).value == -5


@pytest.mark.parametrize(
    ("index", "value", "message"),
    [
        (0x6065, -1, "out of range for UNSIGNED32"),  # Following error window
        (0x605A, 70000, "out of range for INTEGER16"),  # Quick stop option code
        (0x6065, "lots", "not a whole number"),
    ],
)
async def test_invalid_value_is_refused_before_any_frame(
    nodes: SimNodes, index: int, value: int | str, message: str
) -> None:
    requests = SdoTap(nodes, 1)
    sdo = SdoService(nodes)
    with pytest.raises(InvalidValueError, match=message):
        await sdo.write(1, index, 0, value)
    # a read afterwards: once it is answered, every earlier frame has reached the drive
    await sdo.read(1, 0x1000, 0)  # Device type
    requests.remove()
    assert requests.commands() == [UPLOAD_REQUEST]


async def test_dictionary_limits_are_checked_before_sending(nodes: SimNodes) -> None:
    requests = SdoTap(nodes, 1)
    with pytest.raises(InvalidValueError, match="above the maximum 127"):
        await SdoService(nodes).write(1, 0x2006, 0x0A, 200)  # PA-105 node address, 1..127
    await SdoService(nodes).read(1, 0x1000, 0)
    requests.remove()
    assert requests.commands() == [UPLOAD_REQUEST]


async def test_write_to_read_only_object_is_an_sdo_abort(nodes: SimNodes) -> None:
    with pytest.raises(SdoAbortError) as aborted:
        await SdoService(nodes).write(1, 0x6041, 0, 0)  # Statusword
    assert aborted.value.code == 0x06010002
    assert aborted.value.code_hex == "0x06010002"
    assert aborted.value.meaning == "Attempt to write a read-only object"
    assert (aborted.value.index, aborted.value.subindex) == (0x6041, 0)


async def test_read_of_missing_object_is_an_sdo_abort(nodes: SimNodes) -> None:
    with pytest.raises(SdoAbortError) as aborted:
        await SdoService(nodes).read(3, 0x5555, 0)
    assert aborted.value.code == 0x06020000


async def test_entry_unknown_to_the_dictionary_written_with_size(nodes: SimNodes) -> None:
    sdo = SdoService(nodes)
    requests = SdoTap(nodes, 2)
    with pytest.raises(InvalidValueError, match="give the size"):
        await sdo.write(2, 0x5555, 0, 5)
    await sdo.read(2, 0x1000, 0)
    requests.remove()
    assert requests.commands() == [UPLOAD_REQUEST]
    # the drive has no such object either: the write reaches it and it aborts
    with pytest.raises(SdoAbortError) as aborted:
        await sdo.write(2, 0x5555, 0, "E8 03 00 00")
    assert aborted.value.code == 0x06020000


async def test_unknown_node(nodes: SimNodes) -> None:
    with pytest.raises(NodeNotFoundError):
        await SdoService(nodes).read(42, 0x1000, 0)
