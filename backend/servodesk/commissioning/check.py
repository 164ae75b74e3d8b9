"""The field check's I/O: open a bundle, read the drive now, gather who wrote what, and hand
it all to check_core. Used by `POST /api/commissioning/check` and `servodesk check-record`
(which has no server database: everything comes from the bundle and the bus)."""

from __future__ import annotations

import zipfile
from collections.abc import Iterable
from dataclasses import dataclass
from typing import IO

from pydantic import ValidationError

from servodesk.audit import AuditLog
from servodesk.audit.store import AuditFilter
from servodesk.commissioning import check_core as core
from servodesk.commissioning.bundle import AUDIT_CSV, RECORD_JSON
from servodesk.errors import CommTimeoutError, InvalidValueError
from servodesk.faults.service import FaultService
from servodesk.models.commissioning import CommissioningRecord
from servodesk.nodes.access import NodeAccess
from servodesk.od.parser import OdParser
from servodesk.params.paramsets import file_values
from servodesk.sdo import codec
from servodesk.sdo.bulk import BulkOutcome, EntryRead, as_entry_read, read_entries
from servodesk.sdo_aborts import abort_meaning

AUDIT_LIMIT = 10_000
# Members read into memory, by their declared size (a zip can claim any ratio): a record is
# tens of kB, a DCF hundreds, the audit extract of one node a few MB.
MEMBER_MAX = {RECORD_JSON: 8 << 20, AUDIT_CSV: 64 << 20, ".dcf": 8 << 20}
NOT_A_BUNDLE = (
    "not a ServoDesk commissioning bundle: expected a zip with record.json "
    "(GET /api/commissioning/{id}/report?format=zip)"
)


@dataclass
class HandOver:
    """What the check compares against: the record, and for a bundle its DCF and audit CSV."""

    record: CommissioningRecord
    source: str  # record | bundle
    dcf: tuple[bytes, str] | None = None  # (content, member name)
    audit_csv: str | None = None


def open_bundle(file: IO[bytes] | str) -> HandOver:
    """The bundle's record, DCF and audit CSV (blocking: run it in a thread)."""
    try:
        with zipfile.ZipFile(file) as archive:
            names = archive.namelist()
            if RECORD_JSON not in names:
                raise InvalidValueError(NOT_A_BUNDLE)
            record = CommissioningRecord.model_validate_json(_member(archive, RECORD_JSON))
            dcfs = [n for n in names if n.lower().endswith(".dcf") and "/" not in n]
            dcf = (_member(archive, dcfs[0], ".dcf"), dcfs[0]) if dcfs else None
            audit = None
            if AUDIT_CSV in names:
                audit = _member(archive, AUDIT_CSV).decode("utf-8", errors="replace")
    except (zipfile.BadZipFile, EOFError):
        raise InvalidValueError(NOT_A_BUNDLE) from None
    except (ValidationError, ValueError) as error:
        if isinstance(error, InvalidValueError):
            raise
        first = error.errors()[0]["msg"] if isinstance(error, ValidationError) else str(error)
        raise InvalidValueError(f"the bundle's record.json is not a record: {first}") from None
    return HandOver(record, "bundle", dcf, audit)


def _member(archive: zipfile.ZipFile, name: str, kind: str | None = None) -> bytes:
    limit = MEMBER_MAX[kind or name]
    if archive.getinfo(name).file_size > limit:
        raise InvalidValueError(f"the bundle's {name} is larger than {limit >> 20} MiB: not read")
    return archive.read(name)


class FieldCheck:
    """`audit` None and `faults` None (the command line on another PC): who changed what comes
    from the bundle's audit CSV only, and faults from the drive's 1003h only."""

    def __init__(
        self,
        access: NodeAccess,
        parser: OdParser,
        faults: FaultService,
        *,
        audit: AuditLog | None = None,
        history: bool = True,
    ) -> None:
        self._access = access
        self._parser = parser
        self._faults = faults
        self._audit = audit
        self._history = history

    async def run(self, hand_over: HandOver, node: int | None = None) -> core.CheckResult:
        record = hand_over.record
        node = record.node if node is None else node
        self._access.info(node)  # NodeNotFoundError before anything is read
        handover = core.handover_time(record)
        notes: list[str] = []
        params = core.record_expected(record)
        pdos = core.record_pdos(record)
        if hand_over.dcf is not None:
            in_dcf, dcf_pdos = core.dcf_expected(await self._dcf_values(hand_over.dcf, node))
            params = in_dcf | params  # the record's own evidence is the newer word
            pdos = pdos if pdos is not None else dcf_pdos
        if not pdos:
            notes.append("no PDO configuration in the hand-over (no pdo step evidence or DCF)")
        pdos = pdos or {}
        firmware_keys = list(core.FIRMWARE.values())
        now = await self._read(node, [*params, *pdos, *firmware_keys])
        writes = await self._writes(hand_over, node)
        parameters = core.differences(params, now, writes, handover)
        pdo_rows = core.differences(pdos, now, writes, handover)
        firmware = core.firmware(record, now)
        faults = await self._faults_since(node, handover, notes)
        return core.CheckResult(
            differs=bool(parameters or pdo_rows or firmware.changed),
            parameters=parameters, pdos=pdo_rows, faults_since=faults, firmware=firmware,
            record_id=record.id, node=node, handover_at=handover, source=hand_over.source,
            checked_parameters=len(params), checked_pdos=len(pdos), notes=notes,
        )  # fmt: skip

    async def _dcf_values(self, dcf: tuple[bytes, str], node: int) -> list[core.Expected]:
        data, name = dcf
        model = await self._parser.parse(data, name, node_id=node)
        # only what the drive held (ParameterValue), not the EDS defaults beside it
        return [
            core.Expected(sub.index, sub.subindex, codec.entry_name(model, sub),
                          codec.api_value(value), "dcf")
            for sub, value in file_values(model, node).values()
            if sub.value is not None
        ]  # fmt: skip

    async def _read(self, node: int, keys: Iterable[core.Key]) -> dict[core.Key, core.Reading]:
        """Every key in one bulk read on the node's worker (chunked: other requests for the
        node take their turn between chunks)."""
        model = self._access.od(node)
        found: dict[core.Key, core.Reading] = {}
        subs = []
        for key in dict.fromkeys(keys):
            sub = model.get(*key)
            if sub is None or sub.access == "wo":
                found[key] = core.Reading(error="not in the node's dictionary now")
            else:
                subs.append(sub)
        reads: list[EntryRead] = []
        outcome = await read_entries(self._access.session(node), subs, as_entry_read, reads)
        if outcome is BulkOutcome.STALLED:
            raise CommTimeoutError(node, f"reading its entries (stopped after {len(reads)})")
        for read in reads:
            key = (read.sub.index, read.sub.subindex)
            if read.data is not None:
                found[key] = core.Reading(codec.api_value(codec.decode(read.sub, read.data)))
            elif read.abort_code is not None:
                code = read.abort_code
                found[key] = core.Reading(error=f"SDO abort 0x{code:08X} ({abort_meaning(code)})")
            else:
                found[key] = core.Reading(error="no answer")
        return found

    async def _writes(self, hand_over: HandOver, node: int) -> list[core.Write]:
        since = hand_over.record.created
        writes = [] if hand_over.audit_csv is None else core.csv_writes(hand_over.audit_csv, node)
        writes = [w for w in writes if w.time >= since]
        if self._audit is not None:
            rows = await self._audit.entries(AuditFilter(node=node, since=since, limit=AUDIT_LIMIT))
            known = {(w.audit_id, w.user) for w in writes}
            writes += [
                core.Write(r.id, r.time, r.user, r.index, r.subindex, r.new, r.action)
                for r in rows
                if r.result == "ok" and r.index is not None and r.subindex is not None
                and (r.id, r.user) not in known
            ]  # fmt: skip
        return writes

    async def _faults_since(
        self, node: int, handover: float, notes: list[str]
    ) -> list[core.FaultSince]:
        found: list[core.FaultSince] = []
        if self._history:
            history = await self._faults.node_faults(node, AUDIT_LIMIT)
            found += [
                core.FaultSince(source="history", time=f.time, code_hex=f.code_hex, name=f.name_en)
                for f in history.history
                if f.time >= handover
            ]
        device = await self._faults.device_history(node)
        if not device.supported:
            notes.append(f"node {node} keeps no error history of its own (no 1003h)")
        found += [
            core.FaultSince(source="1003h", number=e.number, code_hex=e.fault.code_hex,
                            name=e.fault.name_en)
            for e in device.entries
        ]  # fmt: skip
        return found
