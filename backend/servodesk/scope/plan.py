"""Where each scope signal travels: packed into the node's free TPDOs (sent on every SYNC), or
polled by SDO when no TPDO can carry it. Pure: the node's PDOs and facts in, a plan out.

The user's mapping is kept: the scope only takes TPDOs that are not valid (not in use), and the
plan holds their configuration as it was so stopping the scope writes it back.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Literal

from servodesk.pdo.model import MappedObject, PdoConfig
from servodesk.scope.signals import SignalInfo
from servodesk_protocol import cob_id
from servodesk_protocol.pdo import Direction, default_can_id, restricted_can_id

FRAME_BITS = 64  # classic CAN: 8 data bytes
EVERY_SYNC = 1  # transmission type 1: synchronous, sent on every SYNC
MAX_ENTRIES = 8  # mapping entries per PDO the drives here accept (bytes of a frame)
# TPDO 5 and up have no pre-defined id (CiA 301 §7.3.3): the scope picks base + node id from
# these free ranges (each 40h–7Fh wide, so base + node never reaches the next service)
_EXTRA_BASES = (0x1C0, 0x2C0, 0x3C0, 0x4C0, 0x240, 0x340, 0x440, 0x540)

Source = Literal["pdo", "sdo"]


@dataclass(frozen=True, slots=True)
class Placement:
    signal: SignalInfo
    source: Source
    tpdo: int | None = None
    cob_id: int | None = None
    bit_offset: int = 0  # where it sits in the TPDO's payload
    note: str | None = None  # why SDO


@dataclass(frozen=True)
class NodePlan:
    node: int
    placements: tuple[Placement, ...]
    scope_pdos: tuple[PdoConfig, ...]  # what the scope writes for the capture
    restore_pdos: tuple[PdoConfig, ...]  # those slots as the user had them
    notes: tuple[str, ...] = field(default_factory=tuple)


def plan_node(
    node: int,
    signals: Sequence[SignalInfo],
    current: Sequence[PdoConfig],
    *,
    byte_granular: bool,
    fixed_cob_ids: int,
    taken_ids: Mapping[int, str],
    id_change_needs_reset: bool = False,
) -> NodePlan:
    """Pack `signals` (in order) into the node's invalid TPDOs, first fit, one transmission per
    SYNC; what does not fit or cannot be mapped is polled by SDO. `taken_ids`: CAN ids in use
    on the bus (other nodes' PDOs and services) that a new TPDO must not take.
    `id_change_needs_reset`: the drive takes a new PDO CAN id only after a reset communication
    (Nanotec CANopen article), which would also drop every unsaved setting: only free TPDOs
    that already have a usable id are taken."""
    free = [pdo for pdo in current if pdo.kind == "tpdo" and not pdo.valid]
    used: dict[int, str] = dict(taken_ids)
    services = cob_id.node_services(node)
    used.update({can_id: f"this node's {name}" for can_id, name in services.items()})
    used.update({pdo.cob_id: "this node's PDO" for pdo in current if pdo.valid})
    bins: list[tuple[PdoConfig, list[MappedObject]]] = []
    placements: list[Placement] = []
    notes: list[str] = []
    no_id: list[int] = []
    for signal in signals:
        reason = _unmappable(signal)
        if reason is None:
            slot = _fit(signal, bins, byte_granular)
            if slot is None:
                slot = _open_bin(
                    node, free, bins, used, fixed_cob_ids, no_id, id_change_needs_reset
                )
            if slot is None:
                reason = "has no free TPDO to travel in (the others carry the user's mapping)"
            else:
                pdo, objects = bins[slot]
                offset = sum(obj.bits for obj in objects)
                bits = _bits(signal, byte_granular)
                objects.append(MappedObject(signal.index, signal.subindex, bits))
                placements.append(Placement(signal, "pdo", pdo.number, pdo.cob_id, offset))
                continue
        placements.append(Placement(signal, "sdo", note=f"polled by SDO: it {reason}"))
    if no_id:
        which = ", ".join(f"TPDO{n}" for n in no_id)
        has, is_, it = ("has", "is", "it") if len(no_id) == 1 else ("have", "are", "them")
        why = (
            f"{has} no usable CAN id, and this drive takes a new one only after a reset"
            " communication (which would drop unsaved settings)"
            if id_change_needs_reset
            else f"{is_} free but no CAN id is free for {it}"
        )
        notes.append(f"{which} {why}")
    scope = tuple(replace(pdo, mapping=tuple(objects)) for pdo, objects in bins)
    taken = {pdo.number for pdo in scope}
    restore = tuple(pdo for pdo in current if pdo.kind == "tpdo" and pdo.number in taken)
    return NodePlan(node, tuple(placements), scope, restore, tuple(notes))


def _unmappable(signal: SignalInfo) -> str | None:
    if not signal.readable:
        return "is write-only"
    return signal.mappable_reason


def _bits(signal: SignalInfo, byte_granular: bool) -> int:
    bits = signal.bits if signal.bits is not None else 0
    # a BOOLEAN maps with 1 bit, or a whole byte on drives that map whole bytes only
    return 8 if byte_granular and bits % 8 else bits


def _fit(
    signal: SignalInfo, bins: list[tuple[PdoConfig, list[MappedObject]]], byte_granular: bool
) -> int | None:
    bits = _bits(signal, byte_granular)
    for slot, (_pdo, objects) in enumerate(bins):
        if len(objects) < MAX_ENTRIES and sum(o.bits for o in objects) + bits <= FRAME_BITS:
            return slot
    return None


def _open_bin(
    node: int,
    free: list[PdoConfig],
    bins: list[tuple[PdoConfig, list[MappedObject]]],
    used: dict[int, str],
    fixed_cob_ids: int,
    no_id: list[int],
    keep_id: bool,
) -> int | None:
    while free:
        pdo = free.pop(0)
        can_id = _own_id(pdo, used) if keep_id else _can_id(node, pdo, used, fixed_cob_ids)
        if can_id is None:
            no_id.append(pdo.number)
            continue
        used[can_id] = f"scope TPDO{pdo.number}"
        config = replace(
            pdo,
            cob_id=can_id,
            valid=True,
            transmission_type=EVERY_SYNC,
            inhibit_time_100us=0,
            event_timer_ms=0,
            sync_start=0,
        )
        bins.append((config, []))
        return len(bins) - 1
    return None


def _usable(can_id: int, used: Mapping[int, str]) -> bool:
    return 0 < can_id <= cob_id.CAN_ID_MASK and not restricted_can_id(can_id) and can_id not in used


def _own_id(pdo: PdoConfig, used: Mapping[int, str]) -> int | None:
    return pdo.cob_id if _usable(pdo.cob_id, used) else None


def _can_id(node: int, pdo: PdoConfig, used: Mapping[int, str], fixed_cob_ids: int) -> int | None:
    """The slot's own id when it is usable, else the pre-defined one, else base + node id."""
    default = default_can_id(Direction.TRANSMIT, pdo.number)
    if default is not None and pdo.number <= fixed_cob_ids:
        fixed = default + node  # the drive allows no other
        return fixed if fixed not in used else None
    candidates = [pdo.cob_id]
    if default is not None:
        candidates.append(default + node)
    candidates += [base + node for base in _EXTRA_BASES]
    return next((can_id for can_id in candidates if _usable(can_id, used)), None)
