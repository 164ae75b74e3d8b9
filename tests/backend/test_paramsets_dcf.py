"""Parameter sets against the simulated drives: DCF export, compare, load in a safe order."""

from __future__ import annotations

import dataclasses
import re

import pytest

from servodesk.errors import InvalidValueError
from servodesk.models.paramsets import CompareRow
from servodesk.od import OdObject, OdSub, load_od_bytes
from servodesk.od.datatypes import DataType
from servodesk.params.paramsets import ParamSetService
from servodesk.sdo.service import SdoService
from servodesk_sim.frames import Frame
from tests.backend.sim_nodes import SimNodes

pytestmark = pytest.mark.anyio

SDO_RX = 0x600  # SDO request COB-ID base
DOWNLOAD_COMMANDS = frozenset({0x21, 0x23, 0x27, 0x2B, 0x2F})  # SDO initiate download
COB_ID_INVALID = 0x80000000


class WrittenObjects:
    """(index, sub-index) of every SDO write that reached one drive, in order."""

    def __init__(self, nodes: SimNodes, node: int) -> None:
        self.node = node
        self.keys: list[tuple[int, int]] = []
        self.remove = nodes.sim.add_tap(self._on_frame)

    def _on_frame(self, frame: Frame, origin: object | None) -> None:
        if frame.can_id == SDO_RX + self.node and frame.data[0] in DOWNLOAD_COMMANDS:
            self.keys.append((int.from_bytes(frame.data[1:3], "little"), frame.data[3]))


async def remap_tpdo1(sdo: SdoService, node: int) -> None:
    """Change TPDO1 the way a drive accepts it: invalid, mapping, event timer, valid again."""
    cob_id = (await sdo.read(node, 0x1800, 1)).value  # TPDO1 COB-ID
    assert isinstance(cob_id, int)
    await sdo.write(node, 0x1800, 1, cob_id | COB_ID_INVALID)
    await sdo.write(node, 0x1A00, 0, 0)  # TPDO1 mapping: no entries
    await sdo.write(node, 0x1A00, 1, 0x60410010)  # Statusword
    await sdo.write(node, 0x1A00, 0, 1)
    await sdo.write(node, 0x1800, 5, 50)  # event timer, ms
    await sdo.write(node, 0x1800, 1, cob_id)


def with_value(dcf: str, section: str, literal: str) -> str:
    """The DCF with another ParameterValue in `section`."""
    pattern = rf"(\[{section}\]\n(?:[^\[\n][^\n]*\n)*?ParameterValue=)[^\n]*"
    changed, count = re.subn(pattern, rf"\g<1>{literal}", dcf, count=1)
    assert count == 1, section
    return changed


def rows_by_key(rows: list[CompareRow]) -> dict[tuple[int, int], CompareRow]:
    return {(row.index, row.subindex): row for row in rows}


@pytest.mark.parametrize("node", [1, 2, 3])
async def test_export_change_compare_load_restores(nodes: SimNodes, node: int) -> None:
    sets = ParamSetService(nodes)
    sdo = SdoService(nodes)
    original = (await sdo.read(node, 0x6065, 0)).value  # Following error window
    dcf = (await sets.export_dcf(node)).encode()

    await sdo.write(node, 0x6065, 0, 1234)
    await remap_tpdo1(sdo, node)

    compared = rows_by_key((await sets.compare(node, dcf, f"node{node}.dcf")).rows)
    window = compared[(0x6065, 0)]
    assert (window.device, window.file) == (1234, original)
    assert window.differs_from_file
    assert window.differs_from_default
    assert window.unit == "user units"
    assert compared[(0x1800, 5)].differs_from_file  # event timer
    assert compared[(0x1800, 5)].device == 50
    configuration = {key for key, sub in _entries(nodes, node).items() if sub.access == "rw"}
    differing = {key for key, row in compared.items() if row.differs_from_file}
    assert {(0x6065, 0), (0x1800, 5), (0x1A00, 0)} <= differing & configuration
    # the mapping's first entry differs only where the drive mapped nothing before (Kinco)
    assert differing & configuration <= {(0x6065, 0), (0x1800, 5), (0x1A00, 0), (0x1A00, 1)}

    result = await sets.load_dcf(node, dcf, f"node{node}.dcf")
    assert result.failed == []
    assert result.differences == []
    assert result.written > 100
    assert result.skipped > 0
    assert (await sdo.read(node, 0x6065, 0)).value == original
    assert (await sdo.read(node, 0x1800, 5)).value == 0

    again = rows_by_key((await sets.compare(node, dcf, f"node{node}.dcf")).rows)
    assert not any(again[key].differs_from_file for key in configuration)


def _entries(nodes: SimNodes, node: int) -> dict[tuple[int, int], OdSub]:
    model = nodes.od(node)
    return {(s.index, s.subindex): s for obj in model.objects.values() for s in obj.subs.values()}


async def test_export_holds_device_values_and_identity(nodes: SimNodes) -> None:
    sdo = SdoService(nodes)
    await sdo.write(1, 0x2006, 0x08, 3210)  # PA-103 maximum speed
    text = await ParamSetService(nodes).export_dcf(1)
    assert "[DeviceComissioning]\nNodeID=1\n" in text
    model = load_od_bytes(text.encode(), "node1-mdi-s1c.dcf")
    assert model.format == "dcf"
    assert model.get(0x2006, 0x08).value == 3210  # type: ignore[union-attr]
    assert model.get(0x1018, 1).value == 0x00445653  # type: ignore[union-attr]  # vendor "DVS"
    assert model.get(0x1008, 0).value == "DVS_CANOPEN"  # type: ignore[union-attr]
    assert model.get(0x6041, 0).value is None  # type: ignore[union-attr]  # read-only: no value


async def test_export_leaves_out_what_the_drive_refuses_and_says_so(nodes: SimNodes) -> None:
    model = nodes.od(3)
    extra = OdSub(0x5555, 0, "Not on the drive", DataType.UNSIGNED16, "rw", False, default=7)
    objects = {**model.objects, 0x5555: OdObject(0x5555, "Not on the drive", "var", {0: extra})}
    nodes.set_od(3, dataclasses.replace(model, objects=objects))
    text = await ParamSetService(nodes).export_dcf(3)
    assert "5555h sub 0: SDO abort 0x06020000 (Object does not exist" in text
    exported = load_od_bytes(text.encode(), "node3.dcf")
    assert exported.get(0x5555, 0).value is None  # type: ignore[union-attr]
    assert exported.get(0x6065, 0).value == 100000  # type: ignore[union-attr]


async def test_load_skips_commands_and_read_only_entries(nodes: SimNodes) -> None:
    sets = ParamSetService(nodes)
    dcf = (await sets.export_dcf(3)).encode()
    written = WrittenObjects(nodes, 3)
    result = await sets.load_dcf(3, dcf, "node3.dcf")
    written.remove()
    indices = {index for index, _ in written.keys}
    assert not indices & {0x1010, 0x1011, 0x6040, 0x6041, 0x1000, 0x1018}
    assert result.failed == []
    # the PDO rule in the order the drive saw it: invalid, mapping, count, comm, COB-ID
    tpdo1 = [key for key in written.keys if key[0] in (0x1800, 0x1A00)]
    assert tpdo1[0] == (0x1800, 1)
    assert tpdo1[1] == (0x1A00, 0)
    assert tpdo1[-1] == (0x1800, 1)
    assert tpdo1.index((0x1800, 2)) > max(i for i, k in enumerate(tpdo1) if k[0] == 0x1A00)


async def test_load_reports_refused_entries_and_goes_on(nodes: SimNodes) -> None:
    sets = ParamSetService(nodes)
    text = await sets.export_dcf(1)
    # a value the drive refuses (PA-106 takes 0..6), then one it takes
    bad = with_value(with_value(text, "2006subB", "9"), "2006sub8", "4321")
    result = await sets.load_dcf(1, bad.encode(), "bad.dcf")
    assert [(f.index, f.subindex) for f in result.failed] == [(0x2006, 0x0B)]
    assert result.failed[0].abort_code == "0x06090031"
    assert result.failed[0].message == "Value of parameter written too high (download only)"
    assert result.differences == []
    assert (await SdoService(nodes).read(1, 0x2006, 0x08)).value == 4321


async def test_dcf_of_one_node_loads_onto_another_id() -> None:
    with SimNodes([(1, "mdi-s1c"), (5, "mdi-s1c")]) as nodes:
        sets = ParamSetService(nodes)
        dcf = (await sets.export_dcf(1)).encode()
        result = await sets.load_dcf(5, dcf, "node1-mdi-s1c.dcf")
        # MDi PDO CAN-IDs follow the node id: node 1's 181h becomes node 5's 185h
        assert result.failed == []
        assert result.differences == []
        cob_id = (await SdoService(nodes).read(5, 0x1800, 1)).value  # TPDO1 COB-ID
        assert isinstance(cob_id, int)
        assert cob_id & 0x7FF == 0x185


async def test_compare_without_file_flags_changes_from_the_defaults(nodes: SimNodes) -> None:
    await SdoService(nodes).write(1, 0x2006, 0x08, 3000)  # PA-103
    result = await ParamSetService(nodes).compare(1, None, "")
    rows = rows_by_key(result.rows)
    speed = rows[(0x2006, 0x08)]
    assert (speed.device, speed.default, speed.file) == (3000, 6000, None)
    assert speed.device_text == "0x0BB8 (3000)"
    assert speed.default_text == "0x1770 (6000)"
    assert speed.file_text == ""
    assert speed.differs_from_default
    assert not speed.differs_from_file
    assert speed.unit == "rpm"
    assert speed.name == "Drive parameters PA-96 to PA-111: PA-103 Maximum speed"
    assert not rows[(0x6065, 0)].differs_from_default
    readable = [s for s in _entries(nodes, 1).values() if s.access != "wo"]
    # a parameter set is the writable configuration; status values are listed apart, unflagged
    assert len(rows) == sum(1 for s in readable if s.access in ("rw", "rwr", "rww"))
    read_only = rows_by_key(result.read_only)
    assert len(rows) + len(read_only) == len(readable)
    status = read_only[(0x6041, 0)]  # Statusword
    assert not status.differs_from_default
    assert not status.differs_from_file


async def test_bad_file_is_an_invalid_value(nodes: SimNodes) -> None:
    with pytest.raises(InvalidValueError, match="not an EDS or DCF"):
        await ParamSetService(nodes).load_dcf(1, b"hello", "x.dcf")
