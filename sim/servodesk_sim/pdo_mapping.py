"""PDO parameters of a simulated drive: which mapping entries, counts, COB-IDs and transmission
types it accepts (raising SdoAbort), and the values its mapped objects hold.

The layout itself (entry format, packing, COB-ID bits, transmission types) is
servodesk_protocol.pdo, shared with the app's PDO service.
"""

from __future__ import annotations

from collections.abc import Sequence

from canopen.objectdictionary import ODVariable
from canopen.objectdictionary.datatypes import BOOLEAN

from servodesk_protocol.pdo import (
    CAN_ID_MASK,
    COB_EXTENDED,
    COB_ID_BITS,
    COB_INVALID,
    DUMMY_BITS,
    EVENT_DRIVEN,
    EVENT_RTR,
    MAX_ENTRIES,
    MAX_PDO_BITS,
    SYNC_CYCLIC_MAX,
    SYNC_RTR,
    Direction,
    MapEntry,
    restricted_can_id,
    total_bits,
)
from servodesk_protocol.sdo_abort import (
    INVALID_VALUE,
    NO_OBJECT,
    NOT_MAPPABLE,
    PARAMETER_INCOMPATIBLE,
    PDO_LENGTH_EXCEEDED,
    VALUE_TOO_HIGH,
)
from servodesk_sim.abort_codes import SdoAbort
from servodesk_sim.od_store import ObjectStore

# An entry whose length field differs from the object's size aborts 06040043 (CiA 301 "general
# parameter incompatibility"), not 06070010: that one says the *SDO* data length was wrong,
# which it was not (a 4-byte UNSIGNED32 was written); the parameter contradicts the object.


def accepted_bits(var: ODVariable) -> frozenset[int]:
    """Length fields a mapping entry may carry for `var`."""
    if var.data_type == BOOLEAN:
        # CiA 301 maps BOOLEAN as 1 bit; python-canopen's PDO code counts it as one byte, so a
        # master built on it writes 8. Both address the same value.
        return frozenset({1, 8})
    return frozenset({len(var)})


def check_entry(
    store: ObjectStore, entry: MapEntry, direction: Direction, *, byte_granular: bool
) -> None:
    """Refuse a mapping entry the drive cannot map (raises SdoAbort)."""
    if entry.is_dummy:
        if not store.has(entry.index):
            raise SdoAbort(NO_OBJECT, f"dummy entry {entry.index:04X}h not supported")
        allowed = frozenset({DUMMY_BITS[entry.index]})
    else:
        var = store.variable(entry.index, entry.subindex)  # 06020000 / 06090011
        if not var.pdo_mappable:
            raise SdoAbort(NOT_MAPPABLE, f"{entry.index:04X}h:{entry.subindex:02X} not mappable")
        # MDi-S1-C manual §5.2 1600h: an RPDO target must be writable; a TPDO source readable.
        usable = var.writable if direction is Direction.RECEIVE else var.readable
        if not usable:
            raise SdoAbort(NOT_MAPPABLE, f"{entry.index:04X}h access {var.access_type}")
        allowed = accepted_bits(var)
    if byte_granular and entry.bits % 8:
        # MDi-S1-C manual §5.2 1600h note: "只支持按字节映射，不支持按位映射". A bit field is an
        # object the drive cannot map at all, hence 06040041 rather than a length error.
        raise SdoAbort(NOT_MAPPABLE, f"{entry.bits}-bit entry: byte-granular mapping only")
    if entry.bits not in allowed:
        raise SdoAbort(PARAMETER_INCOMPATIBLE, f"length {entry.bits} for {entry.index:04X}h")


def highest_entry(store: ObjectStore, mapping_index: int) -> int:
    """Number of entry sub-indices the mapping object has (at most MAX_ENTRIES)."""
    count = 0
    while count < MAX_ENTRIES and store.has(mapping_index, count + 1):
        count += 1
    return count


def check_count(
    store: ObjectStore,
    mapping_index: int,
    count: int,
    direction: Direction,
    *,
    byte_granular: bool,
) -> None:
    """Checks for writing sub 0 = `count`: entries 1..count must be valid and fit in 64 bits."""
    if count > highest_entry(store, mapping_index):
        raise SdoAbort(VALUE_TOO_HIGH, f"{count} entries")
    entries = [MapEntry.from_raw(store.get(mapping_index, sub)) for sub in range(1, count + 1)]
    for entry in entries:
        check_entry(store, entry, direction, byte_granular=byte_granular)
    if total_bits(entries) > MAX_PDO_BITS:
        raise SdoAbort(PDO_LENGTH_EXCEEDED, f"{total_bits(entries)} bits")


def read_fields(store: ObjectStore, entries: Sequence[MapEntry]) -> list[tuple[MapEntry, bytes]]:
    """Each entry with its object's value as the SDO server would read it (dummies: no bytes),
    ready for servodesk_protocol.pdo.pack."""
    return [
        (entry, b"" if entry.is_dummy else store.read_bytes(entry.index, entry.subindex))
        for entry in entries
    ]


def read_mapping(store: ObjectStore, mapping_index: int) -> tuple[MapEntry, ...]:
    """The active entries of a mapping parameter (sub 1..sub 0)."""
    count = min(store.get(mapping_index, 0), MAX_ENTRIES)
    return tuple(MapEntry.from_raw(store.get(mapping_index, sub)) for sub in range(1, count + 1))


def check_cob_id(value: int, current: int, *, fixed_id: int | None) -> None:
    """Refuse a COB-ID write (1400h+n / 1800h+n sub 1) the drive cannot take."""
    if value & COB_EXTENDED:
        raise SdoAbort(INVALID_VALUE, "29-bit identifiers are not supported")
    new_id = value & COB_ID_BITS
    if fixed_id is not None:
        # MDi-S1-C manual §5.2 1400h/1800h, Nanotec article 140Nh:01: only bit 31 (and 30) may
        # change.
        if new_id != fixed_id:
            raise SdoAbort(INVALID_VALUE, f"CAN id is fixed at {fixed_id:#x}")
        return
    if value & COB_INVALID:
        return
    if (current & COB_INVALID) == 0 and new_id != current & COB_ID_BITS:
        # CiA 301 §7.5.2.35: the identifier of a valid PDO must not change.
        raise SdoAbort(INVALID_VALUE, "invalidate the PDO before changing its CAN id")
    if new_id > CAN_ID_MASK or restricted_can_id(new_id):
        raise SdoAbort(INVALID_VALUE, f"CAN id {new_id:#x} is reserved")


def check_transmission_type(value: int, direction: Direction, *, rtr: bool) -> None:
    """Types 0–240, 254, 255; 252/253 only for TPDOs of drives with RTR transmission."""
    if value <= SYNC_CYCLIC_MAX or value in EVENT_DRIVEN:
        return
    # CiA 301 §7.5.2.35: 252/253 are reserved for RPDOs.
    if rtr and direction is Direction.TRANSMIT and value in (SYNC_RTR, EVENT_RTR):
        return
    raise SdoAbort(INVALID_VALUE, f"transmission type {value} not supported")
