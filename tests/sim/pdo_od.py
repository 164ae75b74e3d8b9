"""A small object dictionary for the PDO tests: PDO communication and mapping objects with the
MDi-S1-C manual §5.2 factory COB-IDs, plus a few mappable 60xxh objects and some that are not."""

from __future__ import annotations

from canopen.objectdictionary import ObjectDictionary, ODRecord, ODVariable
from canopen.objectdictionary.datatypes import (
    BOOLEAN,
    INTEGER8,
    INTEGER16,
    INTEGER32,
    UNSIGNED8,
    UNSIGNED16,
    UNSIGNED32,
)

from servodesk_sim.abort_codes import SdoAbort
from servodesk_sim.od_store import LengthCheck, ObjectStore

NODE_ID = 1


def variable(
    index: int,
    sub: int,
    data_type: int,
    *,
    access: str = "rw",
    default: int = 0,
    mappable: bool = False,
    low: int | None = None,
    high: int | None = None,
) -> ODVariable:
    var = ODVariable(f"obj_{index:04X}_{sub:02X}", index, sub)
    var.data_type = data_type
    var.access_type = access
    var.default = default
    var.pdo_mappable = mappable
    var.min = low
    var.max = high
    return var


def record(index: int, members: list[ODVariable]) -> ODRecord:
    rec = ODRecord(f"rec_{index:04X}", index)
    for member in members:
        rec.add_member(member)
    return rec


def factory_rpdo_cob_id(number: int) -> int:
    """MDi-S1-C manual §5.2: 1400h 200h+id valid, 1401h–1403h invalid; PDOs 5–8 unused (id 0)."""
    if number == 1:
        return 0x200 + NODE_ID
    if number <= 4:
        return 0x80000000 | (0x200 + 0x100 * (number - 1) + NODE_ID)
    return 0x80000000


def factory_tpdo_cob_id(number: int) -> int:
    """MDi-S1-C manual §5.2: 1800h 40000180h+id, 1801h–1803h C00002x0h+id; PDOs 5–8 unused."""
    if number == 1:
        return 0x40000180 + NODE_ID
    if number <= 4:
        return 0xC0000000 | (0x180 + 0x100 * (number - 1) + NODE_ID)
    return 0xC0000000


def _pdo_objects(od: ObjectDictionary, pdo_count: int) -> None:
    for n in range(pdo_count):
        for comm, cob_id, subs in (
            (0x1400 + n, factory_rpdo_cob_id(n + 1), 5),
            (0x1800 + n, factory_tpdo_cob_id(n + 1), 6),
        ):
            members = [
                variable(comm, 0, UNSIGNED8, access="ro", default=subs),
                variable(comm, 1, UNSIGNED32, default=cob_id),
                variable(comm, 2, UNSIGNED8, default=255),
                variable(comm, 3, UNSIGNED16),
                variable(comm, 5, UNSIGNED16),
            ]
            if subs == 6:
                members.append(variable(comm, 6, UNSIGNED8))
            od.add_object(record(comm, members))
        for mapping in (0x1600 + n, 0x1A00 + n):
            entries = [variable(mapping, sub, UNSIGNED32) for sub in range(1, 9)]
            od.add_object(record(mapping, [variable(mapping, 0, UNSIGNED8), *entries]))


def pdo_od(pdo_count: int = 4, *, dummies: bool = False) -> ObjectDictionary:
    od = ObjectDictionary()  # type: ignore[no-untyped-call]  # canopen leaves it unannotated
    _pdo_objects(od, pdo_count)
    od.add_object(variable(0x1001, 0, UNSIGNED8, access="ro"))  # Error register
    od.add_object(variable(0x6040, 0, UNSIGNED16, mappable=True))  # Controlword
    od.add_object(variable(0x6041, 0, UNSIGNED16, access="ro", mappable=True))  # Statusword
    od.add_object(variable(0x6060, 0, INTEGER8, mappable=True))  # Modes of operation
    od.add_object(variable(0x6063, 0, INTEGER32, access="ro", mappable=True))  # Position (inc)
    od.add_object(variable(0x6064, 0, INTEGER32, access="ro", mappable=True))  # Position actual
    od.add_object(  # Target torque, 0.1 %: MDi-S1-C manual §5.3 range −1000…1000
        variable(0x6071, 0, INTEGER16, mappable=True, low=-1000, high=1000)
    )
    od.add_object(variable(0x607A, 0, INTEGER32, mappable=True))  # Target position
    od.add_object(variable(0x60FD, 0, UNSIGNED32, access="ro", mappable=True))  # Digital inputs
    od.add_object(  # Digital outputs
        record(
            0x60FE,
            [
                variable(0x60FE, 0, UNSIGNED8, access="ro", default=1),
                variable(0x60FE, 1, UNSIGNED32, mappable=True),
            ],
        )
    )
    od.add_object(variable(0x2000, 0, UNSIGNED8))  # a parameter that is not mappable
    for index in (0x2100, 0x2101, 0x2102):  # switches: BOOLEAN, 1 bit in a PDO
        od.add_object(variable(index, 0, BOOLEAN, mappable=True))
    od.add_object(variable(0x2200, 0, UNSIGNED16, access="wo", mappable=True))  # write-only
    if dummies:
        od.add_object(variable(0x0005, 0, UNSIGNED8, access="const"))  # [DummyUsage] Dummy0005
    return od


def make_store(pdo_count: int = 4, *, dummies: bool = False) -> ObjectStore:
    return ObjectStore(
        pdo_od(pdo_count, dummies=dummies), NODE_ID, length_check=LengthCheck.GENERIC
    )


def write(store: ObjectStore, index: int, sub: int, value: int) -> None:
    """An SDO download of `value` (checked, validators and hooks run)."""
    store.write_bytes(index, sub, store.variable(index, sub).encode_raw(value))


def abort_of(store: ObjectStore, index: int, sub: int, value: int) -> int | None:
    """The SDO abort code a download of `value` gets, or None when it is accepted."""
    try:
        write(store, index, sub, value)
    except SdoAbort as abort:
        return abort.code
    return None
