"""The field check's pure comparison (commissioning/check_core.py), table by table."""

from __future__ import annotations

from typing import Any

import pytest

from servodesk.commissioning import check_core as core
from servodesk.models.commissioning import (
    CommissioningIdentity,
    CommissioningRecord,
    CommissioningStep,
)

HANDOVER = 1000.0


def record(evidence: dict[str, dict[str, Any]], **identity: Any) -> CommissioningRecord:
    steps = [
        CommissioningStep.model_validate({"key": k, "title": k, "evidence": e, "at": HANDOVER})
        for k, e in evidence.items()
    ]
    return CommissioningRecord(
        id=7, node=1, title="t", created=900.0, modes=["pp"], steps=steps, status="done",
        identity=CommissioningIdentity(profile="p", profile_label="P", od_source="s",
                                       od_filename="f", **identity),
    )  # fmt: skip


def row(index: int, sub: int, value: Any, **more: Any) -> dict[str, Any]:
    return {"index": index, "subindex": sub, "name": f"{index:04X}", "value": value} | more


def test_record_expected_parameters_win_over_read_backs() -> None:
    rec = record(
        {
            "communication": {"values": [row(0x1017, 0, 100), row(0x2000, 0, None)]},
            "limits": {"values": [row(0x6085, 0, 1), row(0x607D, 1, 5, abort_code="0x0602")]},
            "parameters": {"objects": [{"index": 0x6085, "subindex": 0, "name": "QS", "new": 9}]},
        }
    )
    found = core.record_expected(rec)
    assert {k: (v.value, v.source) for k, v in found.items()} == {
        (0x1017, 0): (100, "communication"),
        (0x6085, 0): (9, "parameters"),
    }
    assert core.handover_time(rec) == HANDOVER
    assert core.record_pdos(rec) is None


def test_dcf_values_split_and_left_out() -> None:
    items = [
        core.Expected(0x1600, 1, "RPDO1 map", 0x60400010, "dcf"),
        core.Expected(0x1018, 1, "vendor", 1, "dcf"),
        core.Expected(0x1010, 1, "store", 0, "dcf"),
        core.Expected(0x6040, 0, "Controlword", 6, "dcf"),
        core.Expected(0x5FF0, 0, "SIM inject fault", 0, "dcf"),
        core.Expected(0x5FF0, 1, "Vendor object", 3, "dcf"),
        core.Expected(0x6081, 0, "Profile velocity", 4000, "dcf"),
    ]
    settings, pdos = core.dcf_expected(items)
    assert sorted(settings) == [(0x5FF0, 1), (0x6081, 0)]
    assert list(pdos) == [(0x1600, 1)]


@pytest.mark.parametrize(
    ("expected", "now", "same"),
    [
        (5, 5, True),
        (5, 6, False),
        (1.0, 1.0000000001, True),
        (1, 1.5, False),
        ("V1.0 ", "V1.0", True),
        (True, 1, True),
        (None, 0, False),
        ("E8 03", "E8 03", True),
    ],
)
def test_same(expected: Any, now: Any, same: bool) -> None:
    assert core.same(expected, now) is same


W = core.Write
KEY = (0x2006, 8)


@pytest.mark.parametrize(
    ("writes", "now", "who"),
    [
        ([], 5500, None),
        # commissioning wrote 5000 before hand-over; nobody the log knows wrote 5500
        ([W(1, 950, "alice", *KEY, 5000, "param")], 5500, None),
        ([W(1, 950, "alice", *KEY, 5000, "param"), W(2, 1100, "bob", *KEY, 5500, "param")],
         5500, "bob"),
        # the value written in other words: the latest write after hand-over
        ([W(3, 1200, "dave", *KEY, "0x157C", "sdo-write")], 5500, "dave"),
        # the latest write of the value now wins over a later one of another value
        ([W(4, 1100, "bob", *KEY, 5500, "param"), W(5, 1300, "eve", *KEY, 6000, "param")],
         5500, "bob"),
        ([W(6, 1100, "bob", 0x2006, 9, 5500, "param")], 5500, None),  # another object
    ],
)  # fmt: skip
def test_changed_by(writes: list[core.Write], now: Any, who: str | None) -> None:
    write = core.changed_by(writes, KEY, now, HANDOVER)
    assert (None if write is None else write.user) == who


def test_differences_rows() -> None:
    expected = {
        KEY: core.Expected(*KEY, "PA-103", 5000, "parameters"),
        (0x6081, 0): core.Expected(0x6081, 0, "v", 4000, "dcf"),
        (0x6083, 0): core.Expected(0x6083, 0, "a", 10, "dcf"),
    }
    now = {
        KEY: core.Reading(5500),
        (0x6081, 0): core.Reading(4000),
        (0x6083, 0): core.Reading(error="SDO abort 0x06020000 (object does not exist)"),
    }
    writes = [W(2, 1100, "bob", *KEY, 5500, "param")]
    rows = core.differences(expected, now, writes, HANDOVER)
    assert [(r.object, r.at_handover, r.now, r.changed_by, r.error is not None) for r in rows] == [
        ("2006:08", 5000, 5500, "bob", False),
        ("6083:00", 10, None, None, True),
    ]
    assert rows[0].audit_id == 2
    assert rows[0].changed_at == 1100


@pytest.mark.parametrize(
    ("now", "changed"),
    [
        ({(0x100A, 0): "1.0", (0x1018, 3): 2}, []),
        ({(0x100A, 0): "1.1", (0x1018, 3): 2}, ["software_version"]),
        ({(0x100A, 0): "1.0", (0x1018, 3): 3}, ["revision"]),
        ({}, []),  # nothing read: nothing to say changed
    ],
)
def test_firmware(now: dict[core.Key, Any], changed: list[str]) -> None:
    rec = record({}, software_version="1.0", revision=2)
    result = core.firmware(rec, {k: core.Reading(v) for k, v in now.items()})
    assert result.changed_fields == changed
    assert result.changed is bool(changed)
    assert result.at_handover["software_version"] == "1.0"


CSV = (
    '"id","time","finished","user","role","client","node","action","what","index","subindex",'
    '"old","new","result","abort_code","error","message","undo_of"\n'
    '"4","2026-01-02T03:04:05.250Z","","alice","engineer","","1","param","PUT …","2006","08",'
    '"6000","5000","ok","","","",""\n'
    '"5","2026-01-02T03:04:06.000Z","","bob","engineer","","1","sdo-write","PUT …","6081","00",'
    '"\'-5","\'-7","ok","","","",""\n'
    '"6","2026-01-02T03:04:07.000Z","","bob","engineer","","1","sdo-write","PUT …","6081","00",'
    '"1","2","failed","","","",""\n'
    '"7","2026-01-02T03:04:08.000Z","","bob","engineer","","2","sdo-write","PUT …","6081","00",'
    '"1","2","ok","","","",""\n'
    '"8","garbage","","x","engineer","","1","sdo-write","PUT …","zz","00",'
    '"1","2","ok","","","",""\n'
)


def test_csv_writes() -> None:
    writes = core.csv_writes(CSV, node=1)
    assert [(w.audit_id, w.user, w.index, w.subindex, w.new) for w in writes] == [
        (4, "alice", 0x2006, 8, 5000),
        (5, "bob", 0x6081, 0, -7),  # the CSV's formula guard taken off
    ]
    assert writes[0].time == pytest.approx(1767323045.25)
    assert len(core.csv_writes(CSV)) == 3  # every node


def test_summary_lines() -> None:
    rec = record({}, software_version="1.0")
    diff = core.differences(
        {KEY: core.Expected(*KEY, "PA-103", 5000, "parameters")},
        {KEY: core.Reading(5500)}, [W(2, 1100, "bob", *KEY, 5500, "param")], HANDOVER,
    )  # fmt: skip
    result = core.CheckResult(
        differs=True, parameters=diff, pdos=[], faults_since=[],
        firmware=core.firmware(rec, {(0x100A, 0): core.Reading("1.1")}), record_id=7, node=1,
        handover_at=HANDOVER, source="bundle", checked_parameters=1, checked_pdos=0,
    )  # fmt: skip
    lines = core.summary_lines(result)
    assert "parameter 2006:08 PA-103: 5000 → 5500 (changed by bob)" in lines
    assert "firmware software_version: 1.0 → 1.1" in lines
    assert lines[-1] == "differs from hand-over"
