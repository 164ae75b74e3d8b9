"""The pdo step: the mapping for the record's modes (optionally the manuals' recommended one,
applied first: an engineer's write), checked against what each mode needs, and a live check that
listens to every valid TPDO for a few of its periods and compares the rate with what its
communication parameter promises (pdo_rates.py). A node in Pre-operational sends no PDOs, so
the step starts it (NMT start), as the PDO page's live check asks the user to."""

from __future__ import annotations

import asyncio
from typing import Any

from servodesk.access.actor import Role, current_actor
from servodesk.audit import AuditLog
from servodesk.commissioning import pdo_rates as rates
from servodesk.commissioning.evidence import Outcome, step_audit_ids
from servodesk.errors import ForbiddenError, InvalidValueError, PdoInvalidError
from servodesk.models.commissioning import CommissioningRecord
from servodesk.models.network import NmtCommandName
from servodesk.pdo.live import PdoCapture
from servodesk.pdo.model import MappedObject, PdoConfig
from servodesk.pdo.recommended import MODE_NAMES, MODES, mode_needs
from servodesk.pdo.service import PdoService


def pdo_row(pdo: PdoConfig) -> dict[str, Any]:
    """One PDO as the record keeps it (the report's table reads the same fields)."""
    return {
        "pdo": f"{pdo.kind.upper()}{pdo.number}",
        "cob_id": f"{pdo.cob_id:03X}h",
        "valid": pdo.valid,
        "transmission_type": pdo.transmission_type,
        "event_timer_ms": pdo.event_timer_ms,
        "inhibit_time_100us": pdo.inhibit_time_100us,
        "mapping": ", ".join(_object(m) for m in pdo.mapping),
    }


def _object(obj: MappedObject) -> str:
    return f"{obj.index:04X}h:{obj.subindex:02X}" + (f" {obj.name}" if obj.name else "")


async def run(
    pdos: PdoService,
    audit: AuditLog,
    record: CommissioningRecord,
    *,
    apply: bool,
    started: float,
) -> Outcome:
    node = record.node
    supported = record.identity.supported_modes
    modes = [m for m in record.modes if m in MODES and (supported is None or m in supported)]
    facts = pdos.facts(node)
    evidence: dict[str, Any] = {"modes": modes, "applied": False}
    if apply:
        actor = current_actor()
        if not actor.may(Role.ENGINEER):
            raise ForbiddenError(
                f"the {actor.role.label} role may not write a PDO mapping: applying needs the "
                "engineer role; run the step without apply to check the mapping as it is",
                role=actor.role.label,
                required=Role.ENGINEER.label,
            )
        if not modes:
            raise InvalidValueError(
                "no mode of the record runs on this drive: nothing to recommend a mapping for"
            )
        wanted = await pdos.recommended(node, modes)
        try:
            await pdos.apply(node, wanted, actor=actor.user)
        except PdoInvalidError as error:
            return "failed", evidence | {"error": str(error)}, f"the recommended mapping: {error}"
        evidence["applied"] = True
    mapping = await pdos.read(node)
    evidence["pdos"] = [pdo_row(p) for p in mapping if p.valid]
    reasons: list[str] = []
    coverage: list[dict[str, Any]] = []
    for mode in modes:
        needs, source = mode_needs(facts.profile, mode, facts.od, facts.byte_granular)
        missing = rates.missing_objects(needs, mapping)
        coverage.append({"mode": mode, "source": source, "missing": missing})
        if missing:
            reasons.append(f"{MODE_NAMES[mode]} needs {', '.join(missing)} in a valid PDO")
    evidence["coverage"] = coverage
    live, figures_failed = await _live_check(pdos, node, mapping, evidence)
    reasons += figures_failed
    evidence["live"] = live
    evidence["audit_ids"] = await step_audit_ids(audit, node, started)
    if not any(p.kind == "tpdo" and p.valid for p in mapping):
        reasons.append("no valid TPDO: the drive's state would only come by SDO polling")
    if reasons:
        return "failed", evidence, "; ".join(reasons)
    return "done", evidence, None


async def _live_check(
    pdos: PdoService, node: int, mapping: list[PdoConfig], evidence: dict[str, Any]
) -> tuple[list[dict[str, Any]], list[str]]:
    access = pdos.access
    if str(access.info(node).nmt_state) != "operational":
        await access.nmt(node, NmtCommandName.START)
        # no wait for the first frames: a rate is taken from the first frame to the last
        evidence["nmt_started"] = "NMT start sent: a node sends PDOs in Operational only"
    sync = pdos.sync_state()
    period = sync.period_us if sync.producing else sync.heard_period_us
    evidence["sync_period_us"] = period
    tpdos = [p for p in mapping if p.kind == "tpdo" and p.valid]
    promised = {p.cob_id: rates.expected_rate(p, period) for p in tpdos}
    window = rates.window_s(list(promised.values()))
    capture = PdoCapture(pdos.network(), {p.cob_id: p for p in tpdos})
    capture.start()
    try:
        await asyncio.sleep(window)
    finally:
        capture.stop()
    rows: list[dict[str, Any]] = []
    failed: list[str] = []
    for pdo in tpdos:
        expected = promised[pdo.cob_id]
        stats = capture.stats(pdo.cob_id)
        verdict = rates.judge(expected, stats.frames, stats.mean_hz, window)
        rows.append(
            {
                "pdo": f"TPDO{pdo.number}",
                "cob_id": f"{pdo.cob_id:03X}h",
                "expected": expected.basis,
                "expected_hz": None if expected.rate_hz is None else round(expected.rate_hz, 3),
                "frames": stats.frames,
                "measured_hz": None if stats.mean_hz is None else round(stats.mean_hz, 3),
                "ok": verdict.ok,
                "verdict": verdict.text,
            }
        )
        if not verdict.ok:
            failed.append(f"TPDO{pdo.number} ({pdo.cob_id:03X}h): {verdict.text}")
    evidence["window_s"] = window
    return rows, failed
