"""The DCF fragment and the python-canopen script carry exactly the PDO configuration given."""

from __future__ import annotations

import uuid
from pathlib import Path

import can
import canopen
import pytest
from canopen.objectdictionary import ODArray, ODRecord

import servodesk_data
from servodesk.od import load_od_bytes
from servodesk.pdo.export import canopen_snippet, dcf_fragment
from servodesk.pdo.model import PdoConfig
from servodesk_protocol.pdo import comm_index, map_index
from servodesk_sim.runner import run_drives
from tests.backend.test_pdo_validate import NODE, context, recommendation

PROFILES = ["mdi-s1c", "kinco", "cia402"]


def without_no_rtr(index: int, sub: int, value: int) -> int:
    """A COB-ID without bit 30 (no RTR), which follows the drive's default (the MDi sets it)."""
    is_cob_id = sub == 1 and (0x1400 <= index < 0x1600 or 0x1800 <= index < 0x1A00)
    return value & ~0x40000000 if is_cob_id else value


def expected_values(pdo: PdoConfig) -> dict[tuple[int, int], int]:
    comm, mapping = comm_index(pdo.direction, pdo.number), map_index(pdo.direction, pdo.number)
    values = {
        (comm, 1): pdo.cob_id | (0 if pdo.valid else 0x80000000),
        (comm, 2): pdo.transmission_type,
        (mapping, 0): len(pdo.mapping),
    }
    values |= {(mapping, n): o.entry.raw for n, o in enumerate(pdo.mapping, start=1)}
    if pdo.kind == "tpdo":
        values |= {(comm, 3): pdo.inhibit_time_100us, (comm, 5): pdo.event_timer_ms}
    return values


# python-canopen warns (with a deprecated call) that a fragment has no [DeviceInfo]
@pytest.mark.filterwarnings("ignore:The 'warn' method is deprecated:DeprecationWarning")
@pytest.mark.parametrize("profile", PROFILES)
@pytest.mark.parametrize("with_od", [False, True], ids=["cia301-subs", "drive-subs"])
def test_dcf_fragment_reads_back_with_both_importers(
    profile: str, with_od: bool, tmp_path: Path
) -> None:
    pdos = recommendation(profile, ["pp", "pv"])
    od = context(profile).od if with_od else None
    text = dcf_fragment(NODE, pdos, od=od)
    model = load_od_bytes(text.encode(), f"node{NODE}-pdos.dcf")
    path = tmp_path / "pdos.dcf"
    path.write_text(text, encoding="utf-8")
    python_canopen = canopen.import_od(str(path))
    for pdo in pdos:
        for (index, sub), value in expected_values(pdo).items():
            entry = model.get(index, sub)
            assert entry is not None, f"{index:04X}h:{sub:02X} missing"
            assert isinstance(entry.value, int)
            assert without_no_rtr(index, sub, entry.value) == value
            record = python_canopen[index]
            assert isinstance(record, ODRecord | ODArray)
            assert record[sub].value == entry.value


def test_dcf_fragment_keeps_to_the_sub_indices_the_drive_has() -> None:
    # Kinco 1400h stops at sub 2 (no inhibit time / event timer on its RPDOs)
    text = dcf_fragment(NODE, recommendation("kinco", ["pp"]), od=context("kinco").od)
    assert "[1400sub3]" not in text
    assert "[1800sub3]" in text
    assert "[1800sub6]" not in text
    assert "[1400sub2]\nParameterName=Transmission type" in text


@pytest.mark.parametrize("profile", PROFILES)
def test_snippet_compiles_and_names_every_object(profile: str) -> None:
    pdos = recommendation(profile, ["pp", "hm"])
    script = canopen_snippet(NODE, pdos, eds_name=f"{profile}.eds", od=context(profile).od)
    compile(script, f"{profile}_pdos.py", "exec")
    assert f"EDS = '{profile}.eds'" in script
    for pdo in pdos:
        assert f"pdo = node.{pdo.kind}[{pdo.number}]" in script
        for obj in pdo.mapping:
            assert f"map_object(pdo, 0x{obj.index:04X}, 0x{obj.subindex:02X}, {obj.bits})" in script
            assert f"{obj.index:04X}h:{obj.subindex:02X} {obj.name}" in script
    assert script.count("pdo.enabled = False") == sum(not p.valid for p in pdos)


@pytest.mark.parametrize("profile", PROFILES)
def test_snippet_configures_a_simulated_drive(profile: str) -> None:
    """Run the script as a user would, against the simulated drive, and read the PDOs back."""
    node = 7
    channel = f"servodesk-test-{uuid.uuid4().hex}"
    pdos = recommendation(profile, ["pp", "pv"], node=node)
    script = canopen_snippet(
        node,
        pdos,
        eds_name=str(servodesk_data.eds_path(profile)),
        od=context(profile).od,
        interface="virtual",
        channel=channel,
    )
    drive_bus = can.Bus(interface="virtual", channel=channel)
    sim = run_drives(drive_bus, [(node, profile)])
    network = canopen.Network()
    network.NOTIFIER_CYCLE = 0.02  # disconnect() waits one cycle
    try:
        exec(compile(script, "pdos.py", "exec"), {"__name__": "__main__"})
        network.connect(interface="virtual", channel=channel)
        remote = network.add_node(node, str(servodesk_data.eds_path(profile)))
        for pdo in pdos:
            for (index, sub), value in expected_values(pdo).items():
                record = remote.object_dictionary[index]
                if not isinstance(record, ODRecord | ODArray) or sub not in record:
                    continue
                read = remote.sdo[index][sub].raw
                assert without_no_rtr(index, sub, read) == value, f"{index:04X}h:{sub:02X}"
    finally:
        network.disconnect()
        sim.stop()
        drive_bus.shutdown()
