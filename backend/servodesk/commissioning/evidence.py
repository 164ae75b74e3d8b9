"""The automated steps that only read: identity, communication, parameters (from the audit
log), limits. Each returns (status, evidence, reason); the service records it."""

from __future__ import annotations

from typing import Any

import servodesk_data
from servodesk.audit import AuditLog
from servodesk.audit.entry import current_entry
from servodesk.audit.store import AuditFilter
from servodesk.commissioning.reads import label, read_listed, where
from servodesk.models.commissioning import CommissioningRecord, StepStatus
from servodesk.motion.words import mode_key
from servodesk.nodes.access import NodeAccess
from servodesk.sdo.service import SdoService
from servodesk_protocol.cia402 import SUPPORTED_DRIVE_MODES, supported_modes
from servodesk_protocol.nmt import (
    CONSUMER_HEARTBEAT_TIME,
    PRODUCER_HEARTBEAT_TIME,
    parse_consumer_entry,
)

Outcome = tuple[StepStatus, dict[str, Any], str | None]

IDENTITY_OBJECTS = [
    (0x1000, 0),  # Device type
    (0x1008, 0),  # Manufacturer device name
    (0x1009, 0),  # Manufacturer hardware version
    (0x100A, 0),  # Manufacturer software version
    (0x1018, 1),  # Identity: vendor-ID
    (0x1018, 2),  # product code
    (0x1018, 3),  # revision number
    (0x1018, 4),  # serial number
]
LIMIT_OBJECTS = [
    (0x607D, 1),  # Software position limit: min
    (0x607D, 2),  # Software position limit: max
    (0x6080, 0),  # Max motor speed
    (0x607F, 0),  # Max profile velocity
    (0x6072, 0),  # Max torque
    (0x605A, 0),  # Quick stop option code
    (0x6085, 0),  # Quick stop deceleration
]
STORE_COMMANDS = (0x1010, 0x1011)  # store / restore: commands, not values the drive keeps
# The simulated drives' injection objects: never stored, not the drive's settings
SIM_ONLY = range(0x5FF0, 0x6000)
AUDIT_LIMIT = 10_000


async def drive_modes(access: NodeAccess, sdo: SdoService, node: int) -> frozenset[str] | None:
    """The modes the drive announces in 6502h, else its profile's; None when neither says."""
    read = await read_listed(access, sdo, node, [(SUPPORTED_DRIVE_MODES, 0)])
    if read and isinstance(read[0]["value"], int):
        modes = supported_modes(read[0]["value"])
        return frozenset(k for m in modes if (k := mode_key(int(m))) is not None)
    data = access.profile_data(node)
    if data is None:
        return None
    return frozenset(k for m in data.quirks.supported_modes if (k := mode_key(m)) is not None)


async def identity(access: NodeAccess, sdo: SdoService, record: CommissioningRecord) -> Outcome:
    node = record.node
    values = await read_listed(access, sdo, node, IDENTITY_OBJECTS)
    info = access.info(node)
    evidence: dict[str, Any] = {
        "values": values,
        "profile": info.profile,
        "profile_label": info.profile_label,
        "eds": {"source": info.od_source, "filename": info.od_filename},
    }
    # the drive at this node now must be the one the record was made for
    now = {v["index"] << 8 | v["subindex"]: v.get("value") for v in values}
    was = record.identity
    differs = [
        f"{name} {expected} → {now[key]}"
        for key, name, expected in (
            (0x1018_01, "vendor-ID", was.vendor_id),
            (0x1018_02, "product code", was.product_code),
            (0x1018_04, "serial number", was.serial),
        )
        if expected is not None and key in now and now[key] != expected
    ]
    if differs:
        reason = (
            f"another device answers at node {node} ({'; '.join(differs)}): "
            "start a new record for it"
        )
        return "failed", evidence, reason
    return "done", evidence, None


async def communication(
    access: NodeAccess, sdo: SdoService, record: CommissioningRecord, *, bitrate: int | None,
    tool_node_id: int,
) -> Outcome:  # fmt: skip
    node = record.node
    data = access.profile_data(node)
    objects = [(PRODUCER_HEARTBEAT_TIME, 0)]
    consumers = await read_listed(access, sdo, node, [(CONSUMER_HEARTBEAT_TIME, 0)])
    count = consumers[0].get("value") if consumers else None
    if isinstance(count, int):
        objects += [(CONSUMER_HEARTBEAT_TIME, sub) for sub in range(1, count + 1)]
    if data is not None:
        objects += [ref for ref in (data.quirks.node_id_object,) if ref is not None]
        objects += list(data.quirks.bitrate_objects)
    values = consumers + await read_listed(access, sdo, node, objects)
    watching = [
        {"object": v["object"], "producer": producer, "ms": ms}
        for v in values
        if v["index"] == CONSUMER_HEARTBEAT_TIME and v["subindex"] >= 1
        and isinstance(v["value"], int)
        for producer, ms in [parse_consumer_entry(v["value"])]
        if ms
    ]  # fmt: skip
    evidence: dict[str, Any] = {
        "node_id": node,
        "bus_bitrate": bitrate,
        "values": values,
        "heartbeat_producer_ms": next(
            (v["value"] for v in values if v["index"] == PRODUCER_HEARTBEAT_TIME), None
        ),
        "consumers": watching,
        "watching_tool": any(c["producer"] == tool_node_id for c in watching),
        "tool_node_id": tool_node_id,
    }
    if data is not None and data.quirks.bitrate_objects:
        codes = {(v["index"], v["subindex"]): v["value"] for v in values}
        refs = {ref: codes.get(ref) for ref in data.quirks.bitrate_objects}
        if all(isinstance(v, int) for v in refs.values()):
            ints = {ref: int(v) for ref, v in refs.items() if isinstance(v, int)}
            evidence["drive_bitrate"] = servodesk_data.bitrate_of(data, ints)
    return "done", evidence, None


async def limits(access: NodeAccess, sdo: SdoService, record: CommissioningRecord) -> Outcome:
    node = record.node
    objects = list(LIMIT_OBJECTS)
    data = access.profile_data(node)
    if data is not None and data.quirks.max_speed_object not in objects:
        objects.append(data.quirks.max_speed_object)  # the drive's own speed limit
    values = await read_listed(access, sdo, node, objects)
    evidence: dict[str, Any] = {"values": values}
    if not values:
        evidence["note"] = "the node's dictionary lists none of the limit objects"
    return "done", evidence, None


async def changes(
    access: NodeAccess, audit: AuditLog, record: CommissioningRecord, *, simulated: bool
) -> list[dict[str, Any]]:
    """Every successful write of one object to the node since the record was made, oldest
    first, from the audit log (the entries' ids are the proof). On the simulated drives their
    injection objects (5FF0h–5FFFh) are left out."""
    rows = await audit.entries(
        AuditFilter(node=record.node, since=record.created, limit=AUDIT_LIMIT)
    )
    found: list[dict[str, Any]] = []
    for row in sorted(rows, key=lambda r: r.id):
        if row.result != "ok" or row.index is None or row.subindex is None:
            continue
        if row.index in STORE_COMMANDS or (simulated and row.index in SIM_ONLY):
            continue
        found.append(
            {
                "audit_id": row.id,
                "object": where(row.index, row.subindex),
                "index": row.index,
                "subindex": row.subindex,
                "name": label(access, record.node, row.index, row.subindex),
                "old": row.old,
                "new": row.new,
                "by": row.user,
                "at": row.time,
                "action": row.action,
            }
        )
    return found


def settled(entries: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """One line per object: the value before the first write, the last value written."""
    objects: dict[str, dict[str, Any]] = {}
    for entry in entries:
        item = objects.get(entry["object"])
        if item is None:
            item = objects[entry["object"]] = {
                key: entry[key] for key in ("object", "index", "subindex", "name", "old")
            }
            item["audit_ids"] = []
        item["new"] = entry["new"]
        item["audit_ids"].append(entry["audit_id"])
    return list(objects.values())


async def parameters(
    access: NodeAccess, audit: AuditLog, record: CommissioningRecord, *, simulated: bool
) -> Outcome:
    entries = await changes(access, audit, record, simulated=simulated)
    evidence: dict[str, Any] = {"entries": entries, "objects": settled(entries)}
    if not entries:
        evidence["note"] = "nothing was written to this node since the record was made"
    return "done", evidence, None


async def step_audit_ids(audit: AuditLog, node: int, since: float) -> list[int]:
    """The audit entries of what a step wrote: the run's own (its SDO writes are recorded in
    it) and those made for the node meanwhile (by the tool itself too: a jog stopped on a missed
    keep-alive, the heartbeat consumer)."""
    ids: list[int] = []
    entry = current_entry()
    if entry is not None and entry.row.done() and entry.row.exception() is None:
        ids.append(entry.row.result())
    rows = await audit.entries(AuditFilter(node=node, since=since, limit=500))
    ids.extend(row.id for row in rows if row.id not in ids)
    return sorted(ids)
