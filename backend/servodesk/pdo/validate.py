"""Is a set of PDO configurations safe to apply to one node? Every reason it is not, in words.

Pure: the service hands in the node's dictionary and what else uses the bus (`PdoContext`), and
gets back one `Problem` per thing a commissioning engineer has to change, each naming the object
it concerns (mapped object, or the communication / mapping parameter entry).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from servodesk.od import datatypes as dt
from servodesk.od.model import ObjectDictionaryModel, OdSub
from servodesk.pdo.model import MappedObject, PdoConfig
from servodesk.pdo_problems import Owner, PdoKind, Problem, owner_params, problem
from servodesk_protocol import cob_id
from servodesk_protocol.pdo import (
    CAN_ID_MASK,
    DUMMY_BITS,
    EVENT_RTR,
    MAX_ENTRIES,
    MAX_EVENT_TIMER_MS,
    MAX_INHIBIT,
    MAX_PDO_BITS,
    MAX_SYNC_START,
    MAX_TRANSMISSION_TYPE,
    SUB_COB_ID,
    SUB_EVENT_TIMER,
    SUB_INHIBIT,
    SUB_SYNC_START,
    SUB_TRANSMISSION,
    SYNC_CYCLIC_MAX,
    SYNC_RTR,
    comm_index,
    default_can_id,
    map_index,
    restricted_can_id,
    restricted_use,
)

WRITABLE = frozenset({"rw", "wo", "rww", "rwr"})  # an RPDO writes into the object
READABLE = frozenset({"ro", "rw", "rwr", "rww", "const"})  # a TPDO reads it


@dataclass(frozen=True)
class PdoContext:
    node: int
    od: ObjectDictionaryModel  # the node's dictionary
    byte_granular: bool  # MDi/Kinco: whole bytes only
    rpdo_count: int  # PDOs the device has
    tpdo_count: int
    sync_producing: bool  # SYNC is on the bus (produced, heard or named): 080h is taken
    other_ids: Mapping[int, str]  # CAN id -> who uses it, for every other user of the bus
    # TPDO types 252/253 (Nanotec article; the MDi-S1-C manual §5.2 has no RTR-triggered PDOs)
    rtr_supported: bool = True
    # PDOs 1..n whose CAN id follows the node id; only the valid bit may change
    # (MDi-S1-C CANopen manual §5.2 1400h, Nanotec CANopen article: PDOs 1–4)
    fixed_cob_ids: int = 0


def pdo_label(kind: PdoKind, number: int) -> str:
    """`RPDO2`, `TPDO1`: how manuals and users name a PDO."""
    return f"{kind.upper()}{number}"


def object_label(index: int, subindex: int, name: str | None) -> str:
    """`6040h:00 Controlword`."""
    text = f"{index:04X}h:{subindex:02X}"
    return f"{text} {name}" if name else text


def used_ids(node: int, pdos: Sequence[PdoConfig]) -> dict[int, str]:
    """The CAN ids node `node` uses: EMCY, SDO, heartbeat and the COB-IDs of its valid PDOs."""
    ids: dict[int, str] = {
        can_id: Owner("owner.node_service", node=node, service=service)
        for can_id, service in cob_id.node_services(node).items()
    }
    for pdo in pdos:
        if pdo.valid:
            ids[pdo.cob_id] = Owner(
                "owner.node_pdo", node=node, pdo=pdo_label(pdo.kind, pdo.number)
            )
    return ids


def validate(pdos: Sequence[PdoConfig], ctx: PdoContext) -> list[Problem]:
    """Every problem with applying `pdos` to node `ctx.node`; empty when they can be applied."""
    problems: list[Problem] = []
    seen: set[tuple[PdoKind, int]] = set()
    for pdo in pdos:
        key = (pdo.kind, pdo.number)
        if key in seen:
            problems.append(_problem(pdo, "pdo.twice", _comm(pdo)))
            continue
        seen.add(key)
        problems += _check_number(pdo, ctx)
        problems += _check_mapping(pdo, ctx)
        problems += _check_transmission(pdo, ctx)
        problems += _check_timers(pdo, ctx)
        problems += _check_cob_id(pdo, ctx)
    problems += _check_collisions(pdos, ctx)
    return problems


def _problem(
    pdo: PdoConfig,
    message_id: str,
    index: int | None = None,
    subindex: int | None = None,
    /,
    **params: str | int,
) -> Problem:
    label = pdo_label(pdo.kind, pdo.number)
    return problem(pdo.kind, pdo.number, message_id, index, subindex, pdo=label, **params)


def _comm(pdo: PdoConfig) -> int:
    return comm_index(pdo.direction, pdo.number) if pdo.number >= 1 else 0


def _map(pdo: PdoConfig) -> int:
    return map_index(pdo.direction, pdo.number) if pdo.number >= 1 else 0


def _check_number(pdo: PdoConfig, ctx: PdoContext) -> list[Problem]:
    count = ctx.rpdo_count if pdo.kind == "rpdo" else ctx.tpdo_count
    if 1 <= pdo.number <= count:
        return []
    return [_problem(pdo, "pdo.no_such", _comm(pdo), count=count, kind=pdo.kind.upper())]


def _check_mapping(pdo: PdoConfig, ctx: PdoContext) -> list[Problem]:
    problems = [p for obj in pdo.mapping for p in _check_entry(pdo, obj, ctx)]
    if len(pdo.mapping) > MAX_ENTRIES:
        many = {"objects": len(pdo.mapping), "max": MAX_ENTRIES}
        problems.append(_problem(pdo, "pdo.too_many_objects", _map(pdo), 0, **many))
    bits = sum(obj.bits for obj in pdo.mapping)
    if bits > MAX_PDO_BITS:
        many = {"bits": bits, "max": MAX_PDO_BITS}
        problems.append(_problem(pdo, "pdo.too_many_bits", _map(pdo), 0, **many))
    return problems


def _check_entry(pdo: PdoConfig, obj: MappedObject, ctx: PdoContext) -> list[Problem]:
    if obj.index in DUMMY_BITS:
        return _check_dummy(pdo, obj, ctx)
    sub = ctx.od.get(obj.index, obj.subindex)
    what = object_label(obj.index, obj.subindex, sub.name if sub else obj.name)
    if sub is None:
        return [_entry_problem(pdo, obj, "pdo.not_in_dictionary", what=what)]
    found: list[Problem] = []
    if not sub.pdo_mappable:
        found.append(_entry_problem(pdo, obj, "pdo.not_mappable", what=what))
    if pdo.kind == "rpdo" and sub.access not in WRITABLE:
        found.append(_entry_problem(pdo, obj, "pdo.read_only", what=what, access=sub.access))
    if pdo.kind == "tpdo" and sub.access not in READABLE:
        found.append(_entry_problem(pdo, obj, "pdo.write_only", what=what))
    size_problem = _size_problem(obj, sub, ctx.byte_granular)
    if size_problem:
        message_id, params = size_problem
        found.append(_entry_problem(pdo, obj, message_id, what=what, **params))
    return found


def _entry_problem(
    pdo: PdoConfig, obj: MappedObject, message_id: str, **params: str | int
) -> Problem:
    label = pdo_label(pdo.kind, pdo.number)
    return problem(pdo.kind, pdo.number, message_id, obj.index, obj.subindex, pdo=label, **params)


def _size_problem(
    obj: MappedObject, sub: OdSub, byte_granular: bool
) -> tuple[str, dict[str, str | int]] | None:
    size = dt.bit_size(sub.data_type)
    type_name = _type_name(sub.data_type)
    if size is None:
        return "pdo.no_fixed_size", {"type": type_name}
    if sub.data_type == dt.DataType.BOOLEAN and obj.bits not in (1, 8):
        return "pdo.wrong_bits_boolean", {"type": type_name, "bits": obj.bits}
    if sub.data_type != dt.DataType.BOOLEAN and obj.bits != size:
        return "pdo.wrong_bits", {"type": type_name, "want": size, "bits": obj.bits}
    if byte_granular and obj.bits % 8:
        return "pdo.whole_bytes", {"bits": obj.bits}
    return None


def _check_dummy(pdo: PdoConfig, obj: MappedObject, ctx: PdoContext) -> list[Problem]:
    dummy = {"dummy": f"{obj.index:04X}", "type": _type_name(obj.index)}
    if obj.index not in ctx.od.device.dummy_usage:
        return [_entry_problem(pdo, obj, "pdo.dummy_unsupported", **dummy)]
    if obj.bits != DUMMY_BITS[obj.index]:
        want = DUMMY_BITS[obj.index]
        return [_entry_problem(pdo, obj, "pdo.dummy_bits", **dummy, want=want, bits=obj.bits)]
    return []


def _check_transmission(pdo: PdoConfig, ctx: PdoContext) -> list[Problem]:
    t = pdo.transmission_type
    sub = (_comm(pdo), SUB_TRANSMISSION)
    if not 0 <= t <= MAX_TRANSMISSION_TYPE:
        return [_problem(pdo, "pdo.transmission_range", *sub, t=t)]
    if SYNC_CYCLIC_MAX < t < SYNC_RTR:
        return [_problem(pdo, "pdo.transmission_reserved", *sub, t=t)]
    if t in (SYNC_RTR, EVENT_RTR):
        if pdo.kind == "rpdo":
            return [_problem(pdo, "pdo.rtr_rpdo", *sub, t=t)]
        if not ctx.rtr_supported:
            return [_problem(pdo, "pdo.rtr_unsupported", *sub, t=t)]
    # a synchronous PDO without SYNC is a warning, not a problem of the mapping (sync_rule.py)
    return []


def _check_timers(pdo: PdoConfig, ctx: PdoContext) -> list[Problem]:
    problems: list[Problem] = []
    comm = _comm(pdo)
    for value, limit, sub, what in (
        (pdo.inhibit_time_100us, MAX_INHIBIT, SUB_INHIBIT, "inhibit"),
        (pdo.event_timer_ms, MAX_EVENT_TIMER_MS, SUB_EVENT_TIMER, "event_timer"),
        (pdo.sync_start, MAX_SYNC_START, SUB_SYNC_START, "sync_start"),
    ):
        if not 0 <= value <= limit:
            range_id = f"pdo.{what}_range"
            problems.append(_problem(pdo, range_id, comm, sub, value=value, limit=limit))
        # an RPDO ignores these (it receives, it does not send); a TPDO needs the entry
        elif (
            value
            and pdo.kind == "tpdo"
            and comm in ctx.od.objects
            and ctx.od.get(comm, sub) is None
        ):
            entry = f"{comm:04X}h:{sub:02X}"
            problems.append(_problem(pdo, f"pdo.{what}_missing", comm, sub, entry=entry))
    return problems


def _check_cob_id(pdo: PdoConfig, ctx: PdoContext) -> list[Problem]:
    where = (_comm(pdo), SUB_COB_ID)
    can_id = pdo.cob_id
    if not 0 <= can_id <= CAN_ID_MASK:
        return [_problem(pdo, "pdo.can_id_range", *where, can_id=f"{can_id:X}")]
    fixed = default_can_id(pdo.direction, pdo.number)
    if fixed is not None and pdo.number <= ctx.fixed_cob_ids and can_id != fixed + ctx.node:
        at = {"fixed": f"{fixed + ctx.node:X}", "base": f"{fixed:X}"}
        return [_problem(pdo, "pdo.can_id_fixed", *where, can_id=f"{can_id:X}", **at)]
    if pdo.valid and restricted_can_id(can_id):
        use = restricted_use(can_id)
        return [_problem(pdo, "pdo.can_id_reserved", *where, can_id=f"{can_id:X}", use=use)]
    return []


def _check_collisions(pdos: Sequence[PdoConfig], ctx: PdoContext) -> list[Problem]:
    users: dict[int, str] = dict(ctx.other_ids)
    if ctx.sync_producing:
        users.setdefault(cob_id.SYNC, Owner("owner.sync"))  # the default COB-ID of 1005h
    if 1 <= ctx.node <= cob_id.MAX_NODE_ID:
        for can_id, service in cob_id.node_services(ctx.node).items():
            users.setdefault(can_id, Owner("owner.this_node", service=service))
    problems: list[Problem] = []
    seen: set[tuple[PdoKind, int]] = set()
    for pdo in pdos:
        if not pdo.valid or (pdo.kind, pdo.number) in seen:  # a repeat is reported as such
            continue
        seen.add((pdo.kind, pdo.number))
        user = users.get(pdo.cob_id)
        if user is not None:
            where = (_comm(pdo), SUB_COB_ID)
            used = {"can_id": f"{pdo.cob_id:X}", **owner_params(user)}
            problems.append(_problem(pdo, "pdo.can_id_used", *where, **used))
        else:
            users[pdo.cob_id] = Owner("owner.pdo", pdo=pdo_label(pdo.kind, pdo.number))
    return problems


def _type_name(data_type: int) -> str:
    try:
        return dt.DataType(data_type).name
    except ValueError:
        return f"data type {data_type:04X}h"
