"""store_verify: store (1010h:01 "save", the parameter service's store), reset the node, wait
for its boot-up (the monitor's boot-up waiters, no polling), read back every value the record
set and name each one the drive did not keep. The step that catches "it worked until the first
power cycle"."""

from __future__ import annotations

import asyncio
import math
import time
from typing import Any

from servodesk.audit import AuditLog
from servodesk.commissioning import evidence as ev
from servodesk.commissioning.reads import read_listed
from servodesk.errors import CommTimeoutError
from servodesk.models.commissioning import CommissioningRecord
from servodesk.models.network import NmtCommandName
from servodesk.nodes.registry import NodeRegistry
from servodesk.params.service import ParamService
from servodesk.sdo.service import SdoService


class BootTimeoutError(CommTimeoutError):
    """The node did not boot after the reset; the step is recorded failed with this."""


def _same(expected: Any, now: Any) -> bool:
    numbers = isinstance(expected, int | float) and isinstance(now, int | float)
    if numbers and (isinstance(expected, float) or isinstance(now, float)):
        return math.isclose(expected, now, rel_tol=1e-6, abs_tol=1e-9)
    return bool(expected == now)


async def _expected(
    registry: NodeRegistry, sdo: SdoService, audit: AuditLog, record: CommissioningRecord,
    tool_node_id: int, simulated: bool,
) -> list[dict[str, Any]]:  # fmt: skip
    """What must survive: the values the record set (audit log), then the communication
    values as the drive holds them now (node id, bitrate objects, 1016h, 1017h)."""
    wanted: dict[str, dict[str, Any]] = {}
    for item in ev.settled(await ev.changes(registry, audit, record, simulated=simulated)):
        wanted[item["object"]] = {**item, "expected": item["new"], "source": "parameters"}
    _, comm, _ = await ev.communication(
        registry, sdo, record, bitrate=None, tool_node_id=tool_node_id
    )
    for value in comm["values"]:
        if value["object"] not in wanted and "abort_code" not in value:
            wanted[value["object"]] = {
                key: value[key] for key in ("object", "index", "subindex", "name")
            } | {"old": None, "expected": value["value"], "source": "communication"}
    return list(wanted.values())


async def run(
    registry: NodeRegistry, sdo: SdoService, params: ParamService, audit: AuditLog,
    record: CommissioningRecord, *, boot_wait: float, tool_node_id: int, simulated: bool,
) -> ev.Outcome:  # fmt: skip
    node = record.node
    checks = await _expected(registry, sdo, audit, record, tool_node_id, simulated)
    # store and reset as one transaction: no other request lands between them
    async with registry.session(node).exclusive():
        await params.store(node, confirm=True)
        stored_at = time.time()
        # listen before resetting: a fast drive's boot-up may follow the reset at once
        waiter = asyncio.create_task(registry.wait_boot(node, boot_wait))
        await asyncio.sleep(0)
        try:
            await registry.nmt(node, NmtCommandName.RESET_NODE)
        except BaseException:
            waiter.cancel()
            raise
    if not await waiter:
        state = registry.info(node).nmt_state.value
        raise BootTimeoutError(
            node,
            f"the reset: no boot-up within {boot_wait:g} s (NMT state: {state}). The "
            "parameters were stored; check the drive's power and wiring, then run the step again",
        )
    booted = time.time() - stored_at
    refs = [(c["index"], c["subindex"]) for c in checks]
    now = {(v["index"], v["subindex"]): v for v in await read_listed(registry, sdo, node, refs)}
    lost: list[dict[str, Any]] = []
    for check in checks:
        read = now.get((check["index"], check["subindex"]))
        value = None if read is None else read.get("value")
        check["now"] = value
        if not _same(check["expected"], value):
            lost.append(
                {key: check.get(key) for key in ("object", "index", "subindex", "name", "old")}
                | {"expected": check["expected"], "now": value}
            )
    evidence: dict[str, Any] = {
        "checked": checks,
        "lost": lost,
        "stored_at": stored_at,
        "boot_up_after_s": round(booted, 3),
    }
    if not lost:
        return "done", evidence, None
    named = "; ".join(
        f"{item['object']}{' ' + item['name'] if item['name'] else ''}: "
        f"expected {item['expected']}, now {item['now']}"
        for item in lost
    )
    return "failed", evidence, f"not kept over the reset: {named}"
