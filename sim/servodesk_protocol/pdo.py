"""PDO communication and mapping parameters (CiA 301 §7.5.2.35–§7.5.2.38): layout, packing and
what the numbers mean. I/O-free: the simulated drives and the app's PDO service both use it.

A mapping entry is `index << 16 | subindex << 8 | length in bits` (MDi-S1-C CANopen manual §2.5.4
table 2.41, CiA 301 §7.4.7.3). Mapped objects are packed little-endian, one bit field after the
other, into at most one classic CAN frame (64 bits).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from enum import Enum

from servodesk_protocol import cob_id

RPDO_COMM = 0x1400  # RPDO communication parameter (1400h + n-1)
RPDO_MAP = 0x1600  # RPDO mapping parameter
TPDO_COMM = 0x1800  # TPDO communication parameter
TPDO_MAP = 0x1A00  # TPDO mapping parameter
MAP_OFFSET = 0x200  # mapping parameter index = communication parameter index + 200h
MAX_PDOS = 512  # per direction (1400h–15FFh)

SUB_COB_ID = 1
SUB_TRANSMISSION = 2
SUB_INHIBIT = 3  # 100 µs units
SUB_EVENT_TIMER = 5  # ms
SUB_SYNC_START = 6

COB_INVALID = cob_id.INVALID_BIT  # PDO does not exist / is not valid
COB_NO_RTR = 1 << 30  # TPDO: no RTR allowed
COB_EXTENDED = cob_id.EXTENDED_BIT  # 29-bit identifier
COB_ID_BITS = 0x1FFFFFFF & ~COB_NO_RTR  # the identifier part of a COB-ID value
CAN_ID_MASK = cob_id.CAN_ID_MASK

MAX_TRANSMISSION_TYPE = 0xFF  # sub 2 is UNSIGNED8
MAX_SYNC_START = 240  # sub 6: SYNC start value 0 (unused) or 1–240 (CiA 301 §7.5.2.35)

SYNC_ACYCLIC = 0  # synchronous, sent at the SYNC after an event
SYNC_CYCLIC_MAX = 240  # 1–240: every n-th SYNC
SYNC_RTR = 252  # sample at SYNC, send on RTR
EVENT_RTR = 253  # sample and send on RTR
EVENT_DRIVEN = (254, 255)  # manufacturer-specific / device-profile event

MAX_ENTRIES = 8  # mapping sub 0 range 0–8 (one entry per byte at byte granularity)
MAX_PDO_BITS = 64  # one classic CAN frame
INHIBIT_UNIT_S = 100e-6  # sub 3 counts 100 µs
MAX_INHIBIT = 0xFFFF
MAX_EVENT_TIMER_MS = 0xFFFF

# CiA 301 §7.4.7.2: the data-type indices 0001h–0007h stand for dummy entries that fill gaps.
# Usable only where the OD declares them ([DummyUsage] in the EDS); value = their size in bits.
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


def comm_index(direction: Direction, number: int) -> int:
    """Communication parameter index of PDO `number` (1-based)."""
    base = RPDO_COMM if direction is Direction.RECEIVE else TPDO_COMM
    return base + number - 1


def map_index(direction: Direction, number: int) -> int:
    """Mapping parameter index of PDO `number` (1-based)."""
    return comm_index(direction, number) + MAP_OFFSET


def total_bits(entries: Sequence[MapEntry]) -> int:
    return sum(entry.bits for entry in entries)


def frame_length(entries: Sequence[MapEntry]) -> int:
    """Bytes a PDO with these entries carries."""
    return (total_bits(entries) + 7) // 8


def pack(fields: Sequence[tuple[MapEntry, bytes]]) -> bytes:
    """PDO payload from (entry, little-endian value bytes) pairs; dummies transmit zeros."""
    value = 0
    offset = 0
    for entry, raw in fields:
        if not entry.is_dummy:
            field = int.from_bytes(raw, "little") & ((1 << entry.bits) - 1)
            value |= field << offset
        offset += entry.bits
    return value.to_bytes((offset + 7) // 8, "little")


def unpack(data: bytes, entries: Sequence[MapEntry]) -> list[tuple[MapEntry, bytes]]:
    """PDO payload split into (entry, little-endian bytes of that object); dummies dropped."""
    value = int.from_bytes(data, "little")
    out: list[tuple[MapEntry, bytes]] = []
    offset = 0
    for entry in entries:
        field = (value >> offset) & ((1 << entry.bits) - 1)
        offset += entry.bits
        if not entry.is_dummy:
            out.append((entry, field.to_bytes(entry.byte_length, "little")))
    return out


# CiA 301 §7.3.5: the CAN ids no PDO may use, and what each range is kept for
RESTRICTED_CAN_IDS: tuple[tuple[int, int, str], ...] = (
    (0x000, 0x000, "NMT"),
    (0x001, 0x07F, "reserved"),
    (0x101, 0x180, "TIME and reserved"),
    (0x581, 0x5FF, "SDO responses"),
    (0x601, 0x67F, "SDO requests"),
    (0x6E0, 0x6FF, "reserved"),
    (0x701, 0x77F, "heartbeat / boot-up"),
    (0x780, 0x7FF, "reserved, LSS"),
)


def restricted_can_id(can_id: int) -> bool:
    """CiA 301 §7.3.5 restricted CAN ids (NMT, SYNC/EMCY/TIME, SDO, LSS, error control); an id
    outside 000h–7FFh counts as restricted too."""
    return not 0 <= can_id <= CAN_ID_MASK or any(
        low <= can_id <= high for low, high, _ in RESTRICTED_CAN_IDS
    )


def restricted_use(can_id: int) -> str:
    """Which service CiA 301 §7.3.5 keeps `can_id` for ("reserved" outside the table)."""
    for low, high, service in RESTRICTED_CAN_IDS:
        if low <= can_id <= high:
            return service
    return "reserved"


def default_can_id(direction: Direction, number: int) -> int | None:
    """Pre-defined connection set id without the node id (CiA 301 §7.3.3), PDOs 1–4 only."""
    if not 1 <= number <= 4:
        return None
    first = cob_id.RPDO1 if direction is Direction.RECEIVE else cob_id.TPDO1
    return first + cob_id.PDO_STEP * (number - 1)


def is_synchronous(transmission_type: int) -> bool:
    """Types 0–240 and 252 act on SYNC: they need a SYNC producer on the bus."""
    return transmission_type <= SYNC_CYCLIC_MAX or transmission_type == SYNC_RTR


def transmission_words(transmission_type: int, direction: Direction) -> str:
    """A transmission type in words, as a commissioning engineer reads it."""
    t = transmission_type
    if t == SYNC_ACYCLIC:
        return (
            "synchronous, acyclic (at the next SYNC after a change)"
            if direction is Direction.TRANSMIT
            else "synchronous (applied at the next SYNC)"
        )
    if t == 1:
        return "every SYNC"
    if t <= SYNC_CYCLIC_MAX:
        return f"every {_ordinal(t)} SYNC" if direction is Direction.TRANSMIT else "synchronous"
    if t == SYNC_RTR:
        return "sampled at SYNC, sent on remote request"
    if t == EVENT_RTR:
        return "sent on remote request"
    if t in EVENT_DRIVEN:
        kind = "manufacturer-specific" if t == 254 else "device-profile"
        if direction is Direction.RECEIVE:
            return f"applied on arrival ({kind} event)"
        return f"on change + event timer ({kind} event)"
    return f"reserved ({t})"


def _ordinal(n: int) -> str:
    suffix = "th" if 10 <= n % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(n % 10, "th")
    return f"{n}{suffix}"
