"""PDO parameters: mapping entries (16xxh / 1Axxh), bit packing and COB-ID / type checks.

A mapping entry is `index << 16 | subindex << 8 | length in bits` (MDi-S1-C manual §2.5.4 table
2.41,
CiA 301 §7.4.7.3). Mapped objects are packed little-endian, one bit field after the other.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from canopen.objectdictionary import ODVariable
from canopen.objectdictionary.datatypes import BOOLEAN

from servodesk_sim.abort_codes import (
    INVALID_VALUE,
    NO_OBJECT,
    NOT_MAPPABLE,
    PARAMETER_INCOMPATIBLE,
    PDO_LENGTH_EXCEEDED,
    VALUE_TOO_HIGH,
    SdoAbort,
)
from servodesk_sim.od_store import ObjectStore

RPDO_COMM = 0x1400  # RPDO communication parameter
RPDO_MAP = 0x1600  # RPDO mapping parameter
TPDO_COMM = 0x1800  # TPDO communication parameter
TPDO_MAP = 0x1A00  # TPDO mapping parameter

SUB_COB_ID = 1
SUB_TRANSMISSION = 2
SUB_INHIBIT = 3  # 100 µs units
SUB_EVENT_TIMER = 5  # ms
SUB_SYNC_START = 6

COB_INVALID = 1 << 31  # PDO does not exist / is not valid
COB_NO_RTR = 1 << 30  # TPDO: no RTR allowed
COB_EXTENDED = 1 << 29  # 29-bit identifier (not supported)
COB_ID_BITS = 0x1FFFFFFF & ~COB_NO_RTR  # the identifier part of a COB-ID value
CAN_ID_MASK = 0x7FF

SYNC_CYCLIC_MAX = 240  # 0 acyclic, 1–240 every n-th SYNC
SYNC_RTR = 252  # sample at SYNC, send on RTR (Nanotec article FCh)
EVENT_RTR = 253  # sample and send on RTR (Nanotec article FDh)
EVENT_DRIVEN = (254, 255)

MAX_ENTRIES = 8  # MDi-S1-C manual §5.2 1600h:00 range 0–8
MAX_PDO_BITS = 64  # one classic CAN frame

# CiA 301 "general parameter incompatibility". Chosen over 06070010 for an entry whose length
# field differs from the object's size: 06070010 says the *SDO* data length was wrong, which
# it was not (a 4-byte UNSIGNED32 was written); the parameter contradicts the object.

# CiA 301 §7.4.7.2: the data-type indices 0001h–0007h stand for dummy entries that fill gaps
# (Nanotec article TX mapping "可为间隔使用虚拟对象"). Usable only where the OD declares them
# ([DummyUsage] in the EDS); value = their size in bits.
DUMMY_BITS = {
    0x0001: 1,  # BOOLEAN
    0x0002: 8,  # INTEGER8
    0x0003: 16,  # INTEGER16
    0x0004: 32,  # INTEGER32
    0x0005: 8,  # UNSIGNED8
    0x0006: 16,  # UNSIGNED16
    0x0007: 32,  # UNSIGNED32
}


class Direction(Enum):
    RECEIVE = "receive"  # RPDO: bus → object dictionary
    TRANSMIT = "transmit"  # TPDO: object dictionary → bus


@dataclass(frozen=True, slots=True)
class MapEntry:
    """One mapping entry (sub 1..8 of a mapping parameter)."""

    index: int
    subindex: int
    bits: int

    @classmethod
    def from_raw(cls, raw: int) -> MapEntry:
        return cls((raw >> 16) & 0xFFFF, (raw >> 8) & 0xFF, raw & 0xFF)

    @property
    def raw(self) -> int:
        return (self.index << 16) | (self.subindex << 8) | self.bits

    @property
    def is_dummy(self) -> bool:
        return self.index in DUMMY_BITS

    @property
    def byte_length(self) -> int:
        return (self.bits + 7) // 8


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


def read_mapping(store: ObjectStore, mapping_index: int) -> tuple[MapEntry, ...]:
    """The active entries of a mapping parameter (sub 1..sub 0)."""
    count = min(store.get(mapping_index, 0), MAX_ENTRIES)
    return tuple(MapEntry.from_raw(store.get(mapping_index, sub)) for sub in range(1, count + 1))


def total_bits(entries: tuple[MapEntry, ...] | list[MapEntry]) -> int:
    return sum(entry.bits for entry in entries)


def frame_length(entries: tuple[MapEntry, ...]) -> int:
    """Bytes a PDO with these entries carries."""
    return (total_bits(entries) + 7) // 8


def pack(store: ObjectStore, entries: tuple[MapEntry, ...]) -> bytes:
    """TPDO payload: each entry's current value (as the SDO server would read it), packed."""
    value = 0
    offset = 0
    for entry in entries:
        if not entry.is_dummy:  # dummies transmit zeros
            raw = store.read_bytes(entry.index, entry.subindex)
            field = int.from_bytes(raw, "little") & ((1 << entry.bits) - 1)
            value |= field << offset
        offset += entry.bits
    return value.to_bytes((offset + 7) // 8, "little")


def unpack(data: bytes, entries: tuple[MapEntry, ...]) -> list[tuple[MapEntry, bytes]]:
    """RPDO payload split into (entry, little-endian bytes of that object); dummies dropped."""
    value = int.from_bytes(data, "little")
    out: list[tuple[MapEntry, bytes]] = []
    offset = 0
    for entry in entries:
        field = (value >> offset) & ((1 << entry.bits) - 1)
        offset += entry.bits
        if not entry.is_dummy:
            out.append((entry, field.to_bytes(entry.byte_length, "little")))
    return out


def restricted_can_id(can_id: int) -> bool:
    """CiA 301 §7.3.5 restricted CAN ids (NMT, SYNC/EMCY/TIME, SDO, LSS, error control)."""
    return (
        can_id <= 0x07F
        or 0x101 <= can_id <= 0x180
        or 0x581 <= can_id <= 0x5FF
        or 0x601 <= can_id <= 0x67F
        or 0x6E0 <= can_id <= 0x6FF
        or can_id >= 0x701
    )


def default_can_id(direction: Direction, number: int) -> int | None:
    """Pre-defined connection set id without the node id (CiA 301 §7.3.3), PDOs 1–4 only."""
    if not 1 <= number <= 4:
        return None
    first = 0x200 if direction is Direction.RECEIVE else 0x180
    return first + 0x100 * (number - 1)


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
