"""Reading a node's PDOs from the device: which PDOs it has, and every sub of their
communication (14xxh/18xxh) and mapping (16xxh/1Axxh) parameters as raw numbers.

Raw values (`RawPdo`) are what the apply procedure compares, writes and restores; `to_config`
turns them into the `PdoConfig` the API shows. All reads of one PDO are one step on the node's
worker thread.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace

import canopen
from canopen.sdo.exceptions import SdoAbortedError

from servodesk.errors import SdoAbortError
from servodesk.nodes.session import NodeSession, Transaction
from servodesk.od import ObjectDictionaryModel
from servodesk.pdo.model import DIRECTION, MappedObject, PdoConfig
from servodesk.pdo_problems import PdoKind
from servodesk.sdo import codec
from servodesk_data import DriveData
from servodesk_protocol.pdo import (
    COB_ID_BITS,
    COB_INVALID,
    COB_NO_RTR,
    MAX_ENTRIES,
    MAX_PDOS,
    RPDO_COMM,
    SUB_COB_ID,
    SUB_EVENT_TIMER,
    SUB_INHIBIT,
    SUB_SYNC_START,
    SUB_TRANSMISSION,
    TPDO_COMM,
    MapEntry,
    comm_index,
    map_index,
)
from servodesk_protocol.sdo_abort import NO_OBJECT, NO_SUBINDEX

Key = tuple[int, int]  # (index, sub-index)

# CiA 301 §7.5.2.35/36: the sizes of the communication parameter subs (sub 4 is reserved)
COMM_SIZES: Mapping[int, int] = {
    SUB_COB_ID: 4,  # UNSIGNED32
    SUB_TRANSMISSION: 1,  # UNSIGNED8
    SUB_INHIBIT: 2,  # UNSIGNED16, 100 µs
    SUB_EVENT_TIMER: 2,  # UNSIGNED16, ms
    SUB_SYNC_START: 1,  # UNSIGNED8
}
COUNT_SIZE = 1  # mapping sub 0: UNSIGNED8
ENTRY_SIZE = 4  # mapping entries: UNSIGNED32
PDO_SPAN = MAX_PDOS  # 1400h–15FFh, 1800h–19FFh
KINDS: tuple[tuple[PdoKind, int], ...] = (("rpdo", RPDO_COMM), ("tpdo", TPDO_COMM))
# Aborts that say "this sub does not exist": optional subs (inhibit, event timer, SYNC start)
# the dictionary lists but the device lacks read as 0.
ABSENT = frozenset({NO_OBJECT, NO_SUBINDEX})


Runner = NodeSession | Transaction  # reads run in a transaction or on their own


@dataclass(frozen=True, slots=True, order=True)
class Slot:
    """One PDO of a node: RPDO or TPDO `number` (1-based)."""

    kind: PdoKind
    number: int

    @property
    def comm(self) -> int:
        return comm_index(DIRECTION[self.kind], self.number)

    @property
    def mapping(self) -> int:
        return map_index(DIRECTION[self.kind], self.number)

    @property
    def label(self) -> str:
        return f"{self.kind.upper()}{self.number}"


@dataclass(frozen=True, slots=True)
class RawPdo:
    """Every sub of one PDO as read from the device: (index, sub) -> raw unsigned value."""

    slot: Slot
    values: Mapping[Key, int]

    def get(self, index: int, subindex: int) -> int:
        return self.values.get((index, subindex), 0)


def size_of(slot: Slot, key: Key) -> int:
    index, subindex = key
    if index == slot.comm:
        return COMM_SIZES[subindex]
    return COUNT_SIZE if subindex == 0 else ENTRY_SIZE


def slots(od: ObjectDictionaryModel, data: DriveData | None) -> list[Slot]:
    """The node's PDOs: as many as its profile says (rpdo_count/tpdo_count), else the PDO
    communication objects its dictionary has."""
    counts = None if data is None else (data.quirks.rpdo_count, data.quirks.tpdo_count)
    out: list[Slot] = []
    for kind, base in KINDS:
        if counts is not None:
            count = counts[0] if kind == "rpdo" else counts[1]
            out += [Slot(kind, n) for n in range(1, count + 1)]
        else:
            present = (i for i in sorted(od.objects) if base <= i < base + PDO_SPAN)
            out += [Slot(kind, index - base + 1) for index in present]
    return out


def comm_subs(od: ObjectDictionaryModel, slot: Slot) -> tuple[int, ...]:
    """The communication subs to read and write: those the dictionary has (COB-ID and
    transmission type when it does not describe the object)."""
    obj = od.objects.get(slot.comm)
    if obj is None:
        return (SUB_COB_ID, SUB_TRANSMISSION)
    return tuple(sub for sub in COMM_SIZES if sub in obj.subs)


def entry_subs(od: ObjectDictionaryModel, slot: Slot) -> tuple[int, ...]:
    """The mapping entry subs (1–8) the dictionary has (all 8 when it does not describe it)."""
    obj = od.objects.get(slot.mapping)
    subs = range(1, MAX_ENTRIES + 1)
    return tuple(subs) if obj is None else tuple(sub for sub in subs if sub in obj.subs)


async def read_raw(
    runner: Runner, od: ObjectDictionaryModel, slot: Slot, *, all_entries: bool = False
) -> RawPdo:
    """Read one PDO. With `all_entries` every entry sub is read (what a restore must put back),
    else only the active ones (1..sub 0)."""
    node = runner.node_id
    wanted_comm = comm_subs(od, slot)
    wanted_entries = entry_subs(od, slot)

    def step(remote: canopen.RemoteNode) -> dict[Key, int]:
        values: dict[Key, int] = {}

        def upload(index: int, sub: int, size: int, optional: bool) -> None:
            try:
                data = bytes(remote.sdo.upload(index, sub))
            except SdoAbortedError as abort:
                if optional and int(abort.code) in ABSENT:
                    return  # listed by the dictionary, absent on the device: reads as 0
                raise SdoAbortError(int(abort.code), node, index, sub) from abort
            values[(index, sub)] = int.from_bytes(data[:size], "little")

        for sub in wanted_comm:
            upload(slot.comm, sub, COMM_SIZES[sub], sub not in (SUB_COB_ID, SUB_TRANSMISSION))
        upload(slot.mapping, 0, COUNT_SIZE, False)
        count = values[(slot.mapping, 0)]
        for sub in wanted_entries:
            if all_entries or sub <= count:
                upload(slot.mapping, sub, ENTRY_SIZE, False)
        return values

    what = f"read {slot.label} ({slot.comm:04X}h, {slot.mapping:04X}h)"
    values = await runner.run(step, what=what, index=slot.comm, subindex=SUB_COB_ID)
    return RawPdo(slot, values)


def mapped_name(od: ObjectDictionaryModel, entry: MapEntry) -> str | None:
    sub = od.get(entry.index, entry.subindex)
    return None if sub is None else codec.entry_name(od, sub)


def to_config(raw: RawPdo, od: ObjectDictionaryModel) -> PdoConfig:
    slot = raw.slot
    cob = raw.get(slot.comm, SUB_COB_ID)
    count = min(raw.get(slot.mapping, 0), MAX_ENTRIES)
    entries = [MapEntry.from_raw(raw.get(slot.mapping, sub)) for sub in range(1, count + 1)]
    return PdoConfig(
        kind=slot.kind,
        number=slot.number,
        cob_id=cob & COB_ID_BITS,
        valid=not cob & COB_INVALID,
        transmission_type=raw.get(slot.comm, SUB_TRANSMISSION),
        inhibit_time_100us=raw.get(slot.comm, SUB_INHIBIT),
        event_timer_ms=raw.get(slot.comm, SUB_EVENT_TIMER),
        sync_start=raw.get(slot.comm, SUB_SYNC_START),
        mapping=tuple(
            MappedObject(e.index, e.subindex, e.bits, mapped_name(od, e)) for e in entries
        ),
    )


def with_names(pdo: PdoConfig, od: ObjectDictionaryModel) -> PdoConfig:
    """`pdo` with each mapped object named from the node's dictionary."""
    mapping = tuple(replace(obj, name=mapped_name(od, obj.entry)) for obj in pdo.mapping)
    return replace(pdo, mapping=mapping)


def target_values(before: RawPdo, pdo: PdoConfig, od: ObjectDictionaryModel) -> dict[Key, int]:
    """The raw values that make the device's PDO `pdo`: `before` with the configured subs
    replaced. Entries past the new count keep what they hold (they are inactive); the COB-ID
    keeps its RTR bit (30), which the API does not show."""
    slot = before.slot
    after = dict(before.values)
    cob = (before.get(slot.comm, SUB_COB_ID) & COB_NO_RTR) | pdo.cob_id
    after[(slot.comm, SUB_COB_ID)] = cob if pdo.valid else cob | COB_INVALID
    fields = {
        SUB_TRANSMISSION: pdo.transmission_type,
        SUB_INHIBIT: pdo.inhibit_time_100us,
        SUB_EVENT_TIMER: pdo.event_timer_ms,
        SUB_SYNC_START: pdo.sync_start,
    }
    present = comm_subs(od, slot)
    for sub, value in fields.items():
        if sub in present:
            after[(slot.comm, sub)] = value
    after[(slot.mapping, 0)] = len(pdo.mapping)
    for sub, obj in enumerate(pdo.mapping, start=1):
        after[(slot.mapping, sub)] = obj.entry.raw
    return after


def same_value(slot: Slot, key: Key, expected: int, actual: int) -> bool:
    """A read-back matches: the COB-ID by its valid bit and identifier only (a device may fix
    the RTR bit 30 as it likes), everything else exactly."""
    if key == (slot.comm, SUB_COB_ID):
        meaningful = COB_INVALID | COB_ID_BITS
        return expected & meaningful == actual & meaningful
    return expected == actual
