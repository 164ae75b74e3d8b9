"""The PDO configuration the service reads, validates, applies and returns (the API's `Pdo`).

Pure data: the API schema (servodesk.models.pdo) mirrors it field for field.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from servodesk.pdo_problems import PdoKind
from servodesk_protocol.pdo import Direction, MapEntry

DIRECTION: dict[PdoKind, Direction] = {"rpdo": Direction.RECEIVE, "tpdo": Direction.TRANSMIT}


@dataclass(frozen=True, slots=True)
class MappedObject:
    """One mapped object; `name` is the dictionary's name for it (None when unknown)."""

    index: int
    subindex: int
    bits: int
    name: str | None = None

    @property
    def entry(self) -> MapEntry:
        return MapEntry(self.index, self.subindex, self.bits)


@dataclass(frozen=True, slots=True)
class PdoConfig:
    """One RPDO or TPDO: its communication parameter (14xxh/18xxh) and mapping (16xxh/1Axxh)."""

    kind: PdoKind
    number: int  # 1-based
    cob_id: int  # the CAN identifier (11 bits), without the valid / RTR flag bits
    valid: bool
    transmission_type: int
    inhibit_time_100us: int = 0
    event_timer_ms: int = 0
    sync_start: int = 0
    mapping: tuple[MappedObject, ...] = field(default_factory=tuple)

    @property
    def direction(self) -> Direction:
        return DIRECTION[self.kind]

    @property
    def entries(self) -> tuple[MapEntry, ...]:
        return tuple(obj.entry for obj in self.mapping)
