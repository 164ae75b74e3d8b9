"""Model -> canopen.ObjectDictionary: what RemoteNode's SDO and PDO helpers see."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import canopen
import pytest
from canopen.objectdictionary import ODArray, ODRecord, ODVariable

from servodesk.od import datatypes as dt
from servodesk.od import load_od
from servodesk.od.to_canopen import to_canopen
from tests.od.corpus import corpus, corpus_files, profile_eds_files

NODE = 3
PROFILES = profile_eds_files()


def _entry(od: canopen.ObjectDictionary, index: int, subindex: int = 0) -> Any:
    """Any: canopen does not declare the default_raw/value_raw attributes its importer sets."""
    var = od.get_variable(index, subindex)
    assert var is not None
    return var


def _variables(od: canopen.ObjectDictionary) -> dict[tuple[int, int], ODVariable]:
    found: dict[tuple[int, int], ODVariable] = {}
    for index in od:
        obj = od[index]
        if isinstance(obj, ODVariable):
            found[(index, 0)] = obj
        else:
            for sub in obj.subindices:
                found[(index, sub)] = obj[sub]
    return found


@pytest.mark.parametrize("path", PROFILES, ids=[p.parent.name for p in PROFILES])
def test_profile_eds_matches_python_canopen_import(path: Path) -> None:
    ours = to_canopen(load_od(path), NODE)
    theirs = canopen.import_od(str(path), node_id=NODE)
    assert list(ours) == list(theirs)
    for index in theirs:
        assert type(ours[index]) is type(theirs[index]), f"{index:04X}"
    ours_vars, theirs_vars = _variables(ours), _variables(theirs)
    assert ours_vars.keys() == theirs_vars.keys()
    for key, want in theirs_vars.items():
        got = ours_vars[key]
        fields = (
            *("name", "data_type", "access_type", "default", "default_raw", "relative"),
            *("pdo_mappable", "min", "max"),
        )
        assert {f: getattr(got, f) for f in fields} == {f: getattr(want, f) for f in fields}, key
    assert ours.device_information.vendor_number == theirs.device_information.vendor_number
    assert ours.device_information.allowed_baudrates == theirs.device_information.allowed_baudrates


@pytest.mark.parametrize("path", PROFILES, ids=[p.parent.name for p in PROFILES])
def test_remote_node_reads_the_default_pdo_maps_from_it(path: Path) -> None:
    model = load_od(path)
    network = canopen.Network()  # never connected: PDO subscriptions only register callbacks
    node = canopen.RemoteNode(NODE, to_canopen(model, NODE))
    network.add_node(node)
    node.tpdo.read(from_od=True)  # type: ignore[no-untyped-call]  # canopen leaves it unannotated
    node.rpdo.read(from_od=True)  # type: ignore[no-untyped-call]
    tpdo1 = node.tpdo[1]
    assert tpdo1.cob_id == 0x180 + NODE
    mapping = model.get(0x1A00, 0)  # TPDO1 mapping parameter
    assert mapping is not None
    assert len(tpdo1.map) == mapping.default
    for variable, subindex in zip(tpdo1.map, range(1, len(tpdo1.map) + 1), strict=True):
        entry = model.get(0x1A00, subindex)
        assert entry is not None
        assert isinstance(entry.default, int)
        assert (variable.index, variable.subindex) == (
            entry.default >> 16,
            (entry.default >> 8) & 0xFF,
        )
    assert node.sdo[0x6041].od.data_type == dt.DataType.UNSIGNED16  # Statusword


def test_relative_defaults_move_to_the_requested_node() -> None:
    model = load_od(corpus("ZeroErr_ZeroErr_Driver_V1.5.eds"), node_id=5)
    assert model.get(0x1400, 1).default == 0x205  # type: ignore[union-attr]  # RPDO1 COB-ID
    od = to_canopen(model, 7)
    assert _entry(od, 0x1400, 1).default == 0x207
    assert _entry(od, 0x1400, 1).default_raw == "$NodeID+0x200"
    assert _entry(od, 0x1014).default == 0x87  # COB-ID EMCY
    assert od.node_id == 7


def test_dummies_and_arrays_for_pdo_mapping() -> None:
    od = to_canopen(load_od(corpus("Pilz-Schunk_prbt_0_1.dcf")), 1)
    assert [i for i in range(1, 8) if i in od] == [2, 3, 4, 5, 6, 7]  # [DummyUsage]
    assert isinstance(od[0x1003], ODArray)
    assert isinstance(od[0x1018], ODRecord)


CORPUS = corpus_files()


@pytest.mark.parametrize("path", CORPUS, ids=[p.name for p in CORPUS])
def test_every_default_fits_its_type_for_sdo_writes(path: Path) -> None:
    od = to_canopen(load_od(path, node_id=NODE), NODE)
    for key, var in _variables(od).items():
        if isinstance(var.default, int | float) and not isinstance(var.default, bool):
            data = var.encode_raw(var.default)  # what an SDO download of the default sends
            assert var.decode_raw(data) == pytest.approx(var.default), key
