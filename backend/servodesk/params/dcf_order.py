"""The order in which a parameter set is written to a drive (pure; table-tested).

Writing a DCF entry by entry in file order fails on real drives: a PDO's mapping can only be
changed while the PDO is invalid (MDi-S1-C manual §5.2, CiA 301 §7.5.2.35), its count only after its
entries, and SYNC-related objects depend on each other. So:

1. communication area (1000h–1FFFh) without the PDOs, in index order, except that the SYNC COB-ID
   1005h comes after the cycle period 1006h and window 1007h (MDi-S1-C manual §2.6: a drive may
   refuse
   to become SYNC producer before it has a period);
2. each PDO as a unit, receive PDOs first: its COB-ID with bit 31 set (invalid), mapping count
   0, the mapping entries, the mapping count, the other communication parameters, and last the
   COB-ID from the file (valid again if the file says so);
3. manufacturer area (2000h–5FFFh), then the device profile area (6000h–9FFFh), then the rest.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from servodesk.od import OdSub
from servodesk.od.model import Value
from servodesk_protocol.pdo import MAP_OFFSET

COB_ID_INVALID = 0x80000000  # bit 31 of a PDO COB-ID: PDO does not exist / is not valid
RPDO_COMM = range(0x1400, 0x1600)  # RPDO communication parameter
RPDO_MAP = range(0x1600, 0x1800)  # RPDO mapping parameter
TPDO_COMM = range(0x1800, 0x1A00)  # TPDO communication parameter
TPDO_MAP = range(0x1A00, 0x1C00)  # TPDO mapping parameter
COMMUNICATION = range(0x1000, 0x2000)
MANUFACTURER = range(0x2000, 0x6000)
PROFILE = range(0x6000, 0xA000)

# Objects that are commands, not configuration: writing a saved value back would act
# (store, restore, clear the error history, start a program, switch the drive's state machine).
COMMAND_OBJECTS: frozenset[int] = frozenset(
    {
        0x1003,  # Pre-defined error field (writing sub 0 clears the history)
        0x1010,  # Store parameters
        0x1011,  # Restore default parameters
        0x1F51,  # Program control
        0x6040,  # Controlword
    }
)
WRITABLE = frozenset({"rw", "wo", "rwr", "rww"})
REFUSE_WRITE_ON_DOWNLOAD = 0x1  # CiA 306 ObjFlags bit 0

# index -> the index it must follow (within the communication area)
_AFTER: Mapping[int, int] = {
    0x1005: 0x1007,  # COB-ID SYNC after communication cycle period 1006h / window 1007h
}

Key = tuple[int, int]


@dataclass(frozen=True)
class Write:
    index: int
    subindex: int
    value: Value
    final: bool = True  # False: an intermediate value (PDO invalid, count 0), not the file's


def skip_reason(sub: OdSub) -> str | None:
    """Why an entry of a parameter set is not written, or None when it is."""
    if sub.index in COMMAND_OBJECTS:
        return "a command, not a setting"
    if sub.access not in WRITABLE:
        return "read-only"
    if sub.obj_flags & REFUSE_WRITE_ON_DOWNLOAD:
        return "the file marks it not to be written on download (ObjFlags)"
    return None


def _is_pdo(index: int) -> bool:
    return index in RPDO_COMM or index in RPDO_MAP or index in TPDO_COMM or index in TPDO_MAP


def _comm_index(index: int) -> int:
    """The communication parameter index of a PDO's communication or mapping object."""
    if index in RPDO_MAP or index in TPDO_MAP:
        return index - MAP_OFFSET
    return index


def plan_writes(values: Mapping[Key, Value]) -> list[Write]:
    """`values` (index, sub-index) -> value, already filtered to what is to be written."""
    communication: list[Key] = []
    pdo_units: set[int] = set()
    application: list[Key] = []
    for key in values:
        index = key[0]
        if _is_pdo(index):
            pdo_units.add(_comm_index(index))
        elif index in COMMUNICATION:
            communication.append(key)
        else:
            application.append(key)
    plan = [Write(i, s, values[(i, s)]) for i, s in sorted(communication, key=_comm_order)]
    for comm in sorted(pdo_units):
        plan += _pdo_unit(comm, values)
    plan += [Write(i, s, values[(i, s)]) for i, s in sorted(application, key=_area_order)]
    return plan


def _comm_order(key: Key) -> tuple[int, bool, int, int]:
    index, subindex = key
    return _AFTER.get(index, index), index in _AFTER, index, subindex


def _area_order(key: Key) -> tuple[int, int, int]:
    index, subindex = key
    area = 0 if index in MANUFACTURER else 1 if index in PROFILE else 2
    return area, index, subindex


def _pdo_unit(comm: int, values: Mapping[Key, Value]) -> list[Write]:
    mapping = comm + MAP_OFFSET
    comm_subs = sorted(s for i, s in values if i == comm)
    map_subs = sorted(s for i, s in values if i == mapping and s != 0)
    cob_id = values.get((comm, 1))
    count = values.get((mapping, 0))
    plan: list[Write] = []
    if isinstance(cob_id, int):
        plan.append(Write(comm, 1, cob_id | COB_ID_INVALID, final=False))
    if count is not None:
        plan.append(Write(mapping, 0, 0, final=False))
    plan += [Write(mapping, s, values[(mapping, s)]) for s in map_subs]
    if count is not None:
        plan.append(Write(mapping, 0, count))
    plan += [Write(comm, s, values[(comm, s)]) for s in comm_subs if s != 1]
    if cob_id is not None:
        plan.append(Write(comm, 1, cob_id))
    return plan
