"""export_dcf -> load_od gives back the values, defaults and structure."""

from __future__ import annotations

import io
from pathlib import Path

import canopen
import pytest

from servodesk.od import DataType, ObjectDictionaryModel, export_dcf, load_od, load_od_bytes
from servodesk.od import datatypes as dt
from tests.od.corpus import corpus, corpus_files

NODE = 6
CORPUS = corpus_files()


def _sample_values(model: ObjectDictionaryModel) -> dict[tuple[int, int], object]:
    """A value for every writable entry that differs from its default, so a lost one shows."""
    values: dict[tuple[int, int], object] = {}
    for obj in model.objects.values():
        for sub in obj.subs.values():
            key = (sub.index, sub.subindex)
            if dt.is_integer(sub.data_type):
                low, high = dt.int_range(sub.data_type)
                values[key] = low if sub.default != low else high
            elif dt.is_float(sub.data_type):
                values[key] = -1.25
            elif dt.is_text(sub.data_type):
                values[key] = f"v{sub.index:04X}.{sub.subindex}"
            else:
                values[key] = bytes([sub.subindex, 0xA5])
    return values


@pytest.mark.parametrize("path", CORPUS, ids=[p.name for p in CORPUS])
def test_export_then_load_preserves_values_and_structure(path: Path) -> None:
    model = load_od(path, node_id=NODE)
    values = _sample_values(model)
    text = export_dcf(model, values, node_id=NODE)
    again = load_od_bytes(text.encode(), "export.dcf")
    assert again.format == "dcf"
    assert again.node_id == NODE
    assert [w for w in again.warnings if w.severity == "error"] == []
    assert again.objects.keys() == model.objects.keys()
    for index, obj in model.objects.items():
        twin = again.objects[index]
        assert (twin.name, twin.object_type) == (obj.name, obj.object_type)
        for subindex, sub in obj.subs.items():
            back = twin.subs[subindex]
            where = f"{index:04X}sub{subindex}"
            assert back.value == values[(index, subindex)], where
            assert back.default == sub.default, where
            assert (back.name, back.data_type, back.access, back.relative) == (
                sub.name,
                sub.data_type,
                sub.access,
                sub.relative,
            ), where
            assert (back.low, back.high, back.pdo_mappable) == (sub.low, sub.high, sub.pdo_mappable)
    assert again.device.vendor_number == model.device.vendor_number
    assert again.device.baud_rates == model.device.baud_rates


def test_export_is_deterministic_and_keeps_loaded_parameter_values() -> None:
    model = load_od(corpus("Elmo_elmo.dcf"), node_id=NODE)
    text = export_dcf(model, {}, node_id=NODE)
    assert text == export_dcf(model, {}, node_id=NODE)
    assert "[DeviceComissioning]\nNodeID=6\n" in text
    assert "[1400sub1]" in text
    again = load_od_bytes(text.encode(), "elmo.dcf", node_id=9)
    cob_id = again.get(0x1400, 1)  # RPDO1 COB-ID: "$NODEID+0x200" in the file
    assert cob_id is not None
    assert (cob_id.value, cob_id.value_relative) == (0x209, True)
    assert again.get(0x1603, 2).value is None  # type: ignore[union-attr]


def test_written_text_is_what_strict_tools_expect() -> None:
    model = load_od(corpus("pythoncanopen_sample.eds"))
    text = export_dcf(model, {(0x3002, 0): 5.2, (0x2001, 0): -5, (0x2000, 0): "Axis"}, node_id=2)
    section = text[text.index("[3002]") :].split("\n\n")[0]
    assert "ParameterValue=0x40A66666" in section  # REAL32 as its bit pattern (CiA 306)
    assert "LowLimit=0x40900000" in section
    assert "ParameterValue=-5" in text[text.index("[2001]") :].split("\n\n")[0]
    assert "ParameterValue=Axis" in text[text.index("[2000]") :].split("\n\n")[0]


def test_python_canopen_reads_the_integer_values_back() -> None:
    model = load_od(corpus("ros2canopen_cia402_slave.eds"))
    values = {(0x6060, 0): -1, (0x607A, 0): -123456, (0x1017, 0): 250}
    stream = io.StringIO(export_dcf(model, values, node_id=NODE))
    stream.name = "export.dcf"
    od = canopen.import_od(stream)
    assert od.node_id == NODE
    read_back = [od.get_variable(i) for i in (0x6060, 0x607A, 0x1017)]
    assert [var.value for var in read_back if var is not None] == [-1, -123456, 250]


@pytest.mark.parametrize(
    ("values", "message"),
    [
        ({(0x7777, 0): 1}, "7777h sub 0"),
        ({(0x1017, 0): 70000}, "does not fit UNSIGNED16"),
        ({(0x1017, 0): "fast"}, "expected a number"),
        ({(0x1008, 0): "two\nlines"}, "line break"),
        ({(0x1008, 0): 5}, "expected text"),
    ],
)
def test_export_refuses_values_it_cannot_write(
    values: dict[tuple[int, int], object], message: str
) -> None:
    model = load_od(corpus("ros2canopen_cia402_slave.eds"))
    assert model.get(0x1008) is not None
    assert model.get(0x1008).data_type == DataType.VISIBLE_STRING  # type: ignore[union-attr]
    with pytest.raises(ValueError, match=message):
        export_dcf(model, values, node_id=NODE)
