"""The field check's comparison (pure, table-tested): the drive as it is now against its
hand-over, from values already read. commissioning/check.py does the reading for the API and
for `servodesk check-record`; both answer with `CheckResult`.

What the hand-over held: the record's evidence (parameters step: the last value written;
communication and limits: the values read back) and, for a bundle, the DCF of the drive as
exported with it. The record's evidence wins where both name an object."""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from pydantic import BaseModel, Field

from servodesk.models.commissioning import CommissioningRecord

Key = tuple[int, int]

PDO_RANGE = range(0x1400, 0x1C00)  # RPDO/TPDO communication and mapping parameters
# Not settings: identity (the firmware part is compared on its own), store/restore commands
IDENTITY = frozenset({0x1000, 0x1008, 0x1009, 0x100A, 0x1018})
COMMANDS = frozenset({0x1010, 0x1011})
# Process values a DCF export catches in passing: they change with every move, not a setting
PROCESS = frozenset(
    {
        0x6040,  # Controlword
        0x6060,  # Modes of operation
        0x607A,  # Target position
        0x60FF,  # Target velocity
        0x6071,  # Target torque
        0x60C1,  # Interpolation data record
        0x1005,  # COB-ID SYNC: the tool's SYNC producer bit comes and goes with captures
        0x1006,  # Communication cycle period: likewise set by the scope
    }
)
SIM_OBJECTS = range(0x5FF0, 0x6000)  # the simulated drives' injection objects ("SIM …")
FIRMWARE = {
    "software_version": (0x100A, 0),  # Manufacturer software version
    "hardware_version": (0x1009, 0),  # Manufacturer hardware version
    "revision": (0x1018, 3),  # Identity: revision number
}


def where(index: int, subindex: int) -> str:
    return f"{index:04X}:{subindex:02X}"


@dataclass(frozen=True)
class Expected:
    """One value the hand-over held."""

    index: int
    subindex: int
    name: str | None
    value: Any
    source: str  # parameters | communication | limits | pdo | dcf


@dataclass(frozen=True)
class Reading:
    """One value read now: `error` says why there is none (an abort, not in the dictionary)."""

    value: Any = None
    error: str | None = None


@dataclass(frozen=True)
class Write:
    """One successful audit entry that wrote an object of the node."""

    audit_id: int
    time: float
    user: str
    index: int
    subindex: int
    new: Any
    action: str


class Difference(BaseModel):
    index: int
    subindex: int
    object: str  # "2006:08"
    name: str | None
    at_handover: Any
    now: Any
    changed_by: str | None = Field(description="who wrote it last, where the audit log knows")
    changed_at: float | None = None
    audit_id: int | None = None
    source: str  # where the hand-over value comes from: parameters, communication, limits, pdo, dcf
    error: str | None = None  # why there is no value now (SDO abort, not in the dictionary)


class FaultSince(BaseModel):
    source: str  # history (the tool's fault history) | 1003h (the drive's own, read now)
    time: float | None = None  # unix s; None for 1003h (the drive keeps no time)
    number: int | None = None  # 1003h sub-index: 1 = newest
    code_hex: str
    name: str


class Firmware(BaseModel):
    at_handover: dict[str, Any]
    now: dict[str, Any]
    changed: bool
    changed_fields: list[str] = Field(default_factory=list)


class CheckResult(BaseModel):
    differs: bool = Field(description="a parameter, a PDO entry or the firmware differs")
    parameters: list[Difference]
    pdos: list[Difference]
    faults_since: list[FaultSince]
    firmware: Firmware
    record_id: int
    node: int
    handover_at: float = Field(description="the record's last step time (unix s)")
    source: str = Field(description="record (this server's record) or bundle (an uploaded zip)")
    checked_parameters: int
    checked_pdos: int
    notes: list[str] = Field(default_factory=list)


def handover_time(record: CommissioningRecord) -> float:
    """When the axis was handed over: its last step's time (the record's creation if none)."""
    return max((s.at for s in record.steps if s.at is not None), default=record.created)


def _evidence(record: CommissioningRecord, key: str) -> dict[str, Any]:
    return next((s.evidence for s in record.steps if s.key == key), {})


def _rows(items: Any) -> list[dict[str, Any]]:
    return [i for i in items if isinstance(i, dict)] if isinstance(items, list) else []


def _expected_row(row: dict[str, Any], value_key: str, source: str) -> Expected | None:
    index, subindex = row.get("index"), row.get("subindex")
    if not isinstance(index, int) or not isinstance(subindex, int) or "abort_code" in row:
        return None
    value = row.get(value_key)
    return None if value is None else Expected(index, subindex, row.get("name"), value, source)


def record_expected(record: CommissioningRecord) -> dict[Key, Expected]:
    """The record's own values: communication and limits as read back, then the parameters
    step's last written values over them (the newer word on an object)."""
    found: dict[Key, Expected] = {}
    for key, rows, value_key in (
        ("communication", _rows(_evidence(record, "communication").get("values")), "value"),
        ("limits", _rows(_evidence(record, "limits").get("values")), "value"),
        ("parameters", _rows(_evidence(record, "parameters").get("objects")), "new"),
    ):
        for row in rows:
            item = _expected_row(row, value_key, key)
            if item is not None and item.index not in PDO_RANGE:
                found[(item.index, item.subindex)] = item
    return found


def record_pdos(record: CommissioningRecord) -> dict[Key, Expected] | None:
    """The pdo step's entries (`evidence.values` or `evidence.entries`: {index, subindex,
    value}); None when the step holds none."""
    evidence = _evidence(record, "pdo")
    rows = _rows(evidence.get("values")) or _rows(evidence.get("entries"))
    found = {}
    for row in rows:
        item = _expected_row(row, "value", "pdo")
        if item is not None and item.index in PDO_RANGE:
            found[(item.index, item.subindex)] = item
    return found or None


def _left_out(item: Expected) -> bool:
    if item.index in IDENTITY or item.index in COMMANDS or item.index in PROCESS:
        return True
    return item.index in SIM_OBJECTS and (item.name or "").upper().startswith("SIM")


def dcf_expected(
    entries: Iterable[Expected],
) -> tuple[dict[Key, Expected], dict[Key, Expected]]:
    """A bundle DCF's values split into settings and PDO entries; identity, commands, process
    values and the simulator's injection objects left out."""
    settings: dict[Key, Expected] = {}
    pdos: dict[Key, Expected] = {}
    for item in entries:
        key = (item.index, item.subindex)
        if item.index in PDO_RANGE:
            pdos[key] = item
        elif not _left_out(item):
            settings[key] = item
    return settings, pdos


def same(expected: Any, now: Any) -> bool:
    if isinstance(expected, bool) or isinstance(now, bool):
        return bool(expected == now)
    numbers = isinstance(expected, int | float) and isinstance(now, int | float)
    if numbers and (isinstance(expected, float) or isinstance(now, float)):
        return math.isclose(expected, now, rel_tol=1e-6, abs_tol=1e-9)
    if isinstance(expected, str) and isinstance(now, str):
        return expected.strip() == now.strip()
    return bool(expected == now)


def changed_by(writes: Iterable[Write], key: Key, now: Any, handover: float) -> Write | None:
    """Who put the value there: the latest write of the object that wrote the value it has
    now; else the latest write after the hand-over (a value written in other words, e.g.
    "0x10" for 16); else nobody the audit log knows."""
    mine = sorted(
        (w for w in writes if (w.index, w.subindex) == key), key=lambda w: (w.time, w.audit_id)
    )
    for write in reversed(mine):
        if now is not None and same(write.new, now):
            return write
    after = [w for w in mine if w.time >= handover]
    return after[-1] if after else None


def differences(
    expected: Mapping[Key, Expected],
    now: Mapping[Key, Reading],
    writes: Iterable[Write],
    handover: float,
) -> list[Difference]:
    """Each object whose value now is not the hand-over's, in object order."""
    writes = list(writes)
    found: list[Difference] = []
    for key in sorted(expected):
        item = expected[key]
        reading = now.get(key, Reading(error="not read"))
        if reading.error is None and same(item.value, reading.value):
            continue
        write = changed_by(writes, key, reading.value, handover)
        found.append(
            Difference(
                index=item.index,
                subindex=item.subindex,
                object=where(*key),
                name=item.name,
                at_handover=item.value,
                now=reading.value,
                changed_by=None if write is None else write.user,
                changed_at=None if write is None else write.time,
                audit_id=None if write is None else write.audit_id,
                source=item.source,
                error=reading.error,
            )
        )
    return found


def firmware(record: CommissioningRecord, now: Mapping[Key, Reading]) -> Firmware:
    was = record.identity.model_dump()
    at_handover: dict[str, Any] = {}
    current: dict[str, Any] = {}
    changed: list[str] = []
    for field, key in FIRMWARE.items():
        at_handover[field] = was.get(field)
        reading = now.get(key)
        current[field] = None if reading is None else reading.value
        known = at_handover[field] is not None and current[field] is not None
        if known and not same(at_handover[field], current[field]):
            changed.append(field)
    return Firmware(at_handover=at_handover, now=current, changed=bool(changed),
                    changed_fields=changed)  # fmt: skip


def _cell(text: str) -> str:
    # the audit CSV guards cells that look like formulas with a leading quote (csv_cells.py)
    if text.startswith("'") and text[1:2] in ("=", "+", "-", "@", "\t", "\r"):
        return text[1:]
    return text


def _value(text: str) -> Any:
    if text == "":
        return None
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def _time(text: str) -> float | None:
    try:
        return datetime.fromisoformat(text.replace("Z", "+00:00")).timestamp()
    except ValueError:
        return None


def csv_writes(text: str, node: int | None = None) -> list[Write]:
    """The successful single-object writes of a bundle's audit.csv (audit/store.py columns),
    of `node` when given; rows that do not parse are left out (a hand-edited file)."""
    writes: list[Write] = []
    for row in csv.DictReader(io.StringIO(text)):
        cells = {k: _cell(v or "") for k, v in row.items() if k is not None}
        try:
            index, subindex = int(cells["index"], 16), int(cells["subindex"], 16)
            audit_id, row_node = int(cells["id"]), int(cells["node"])
        except (KeyError, ValueError):
            continue
        when = _time(cells.get("time", ""))
        if cells.get("result") != "ok" or when is None or (node is not None and row_node != node):
            continue
        writes.append(
            Write(audit_id, when, cells.get("user", ""), index, subindex,
                  _value(cells.get("new", "")), cells.get("action", ""))
        )  # fmt: skip
    return writes


def _shown(value: Any) -> str:
    return "—" if value is None else str(value)


def summary_lines(result: CheckResult) -> list[str]:
    """The check in words, one line per difference (the command line prints these)."""
    lines = [
        f"node {result.node}, record {result.record_id}: {result.checked_parameters} "
        f"parameter(s) and {result.checked_pdos} PDO entr(ies) checked"
    ]
    for kind, rows in (("parameter", result.parameters), ("PDO", result.pdos)):
        for row in rows:
            name = f" {row.name}" if row.name else ""
            now = row.error if row.error else _shown(row.now)
            who = f"changed by {row.changed_by}" if row.changed_by else "changed by: unknown"
            lines.append(f"{kind} {row.object}{name}: {_shown(row.at_handover)} → {now} ({who})")
    fw = result.firmware
    for field in fw.changed_fields:
        lines.append(f"firmware {field}: {fw.at_handover[field]} → {fw.now[field]}")
    for fault in result.faults_since:
        lines.append(f"fault ({fault.source}): {fault.code_hex} {fault.name}")
    lines.extend(f"note: {note}" for note in result.notes)
    lines.append("differs from hand-over" if result.differs else "as handed over")
    return lines
