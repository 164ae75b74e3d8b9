"""The hand-over bundle of one record: a zip another ServoDesk can read.

Members: `report.pdf`, `report.html`, the node's DCF as read from the drive now
(`node{N}-{profile}.dcf`, the parameter-set export), each capture the record names
(`captures/servodesk-capture-{id}.rrd` and `.parquet`, the scope's export), the node's audit
entries since the record was made (`audit.csv`, the audit log's CSV export with its cell
escaping) and the record (`record.json`, as `GET /api/commissioning/{id}` answers). What could
not be had (the node is off the bus, a capture was deleted) is named in `missing.txt` instead
of failing the whole bundle.

Memory stays bounded: the audit CSV is streamed to a file chunk by chunk, capture files are
copied into the zip from disk, and the zip itself is written to a temporary file in a worker
thread; the caller streams that file and deletes it."""

from __future__ import annotations

import asyncio
import shutil
import tempfile
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

from servodesk.audit import AuditFilter
from servodesk.commissioning.report import ReportSources
from servodesk.commissioning.report_tables import capture_ids
from servodesk.errors import ServodeskError
from servodesk.models.commissioning import CommissioningRecord

RECORD_JSON = "record.json"
AUDIT_CSV = "audit.csv"


@dataclass
class BundleParts:
    """What goes into the zip: text members, files on disk, and what is missing."""

    texts: dict[str, str | bytes] = field(default_factory=dict)
    files: dict[str, Path] = field(default_factory=dict)
    missing: list[str] = field(default_factory=list)


def bundle_name(record: CommissioningRecord) -> str:
    return f"servodesk-commissioning-{record.id}-node{record.node}.zip"


async def _dcf(sources: ReportSources, record: CommissioningRecord, parts: BundleParts) -> None:
    try:
        text = await sources.paramsets.export_dcf(record.node)
        profile = sources.registry.info(record.node).profile
    except ServodeskError as error:
        parts.missing.append(f"DCF of node {record.node}: {error}")
        return
    parts.texts[f"node{record.node}-{profile}.dcf"] = text


async def _captures(
    sources: ReportSources, record: CommissioningRecord, parts: BundleParts
) -> None:
    ids = [i for step in record.steps for i in capture_ids(step.evidence)]
    for capture_id in dict.fromkeys(ids):
        for fmt in ("rrd", "parquet"):
            try:
                path = await sources.scope.export(capture_id, fmt)
            except ServodeskError as error:
                parts.missing.append(f"capture {capture_id} ({fmt}): {error}")
                continue
            if not path.is_file():
                parts.missing.append(f"capture {capture_id} ({fmt}): no file on disk")
                continue
            parts.files[f"captures/servodesk-capture-{capture_id}.{fmt}"] = path


async def _audit_csv(
    sources: ReportSources, record: CommissioningRecord, folder: Path, parts: BundleParts
) -> None:
    path = folder / AUDIT_CSV
    with path.open("w", encoding="utf-8", newline="") as out:
        async for chunk in sources.audit.csv(AuditFilter(node=record.node, since=record.created)):
            await asyncio.to_thread(out.write, chunk)
    parts.files[AUDIT_CSV] = path


def _write_zip(target: Path, parts: BundleParts) -> None:
    with zipfile.ZipFile(target, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        for name, data in parts.texts.items():
            archive.writestr(name, data)
        for name, path in parts.files.items():
            # .rrd and Parquet are compressed already: stored, not deflated again
            packed = name.endswith((".rrd", ".parquet"))
            kind = zipfile.ZIP_STORED if packed else zipfile.ZIP_DEFLATED
            archive.write(path, name, compress_type=kind)
        if parts.missing:
            archive.writestr("missing.txt", "\n".join(parts.missing) + "\n")


async def build_bundle(
    sources: ReportSources, record: CommissioningRecord, html: str, pdf: bytes
) -> Path:
    """The bundle as a zip in a new temporary directory; the caller removes it with
    `discard()` once sent."""
    folder = Path(await asyncio.to_thread(tempfile.mkdtemp, prefix="servodesk-bundle-"))
    try:
        parts = BundleParts()
        parts.texts["report.pdf"] = pdf
        parts.texts["report.html"] = html
        await _dcf(sources, record, parts)
        await _captures(sources, record, parts)
        await _audit_csv(sources, record, folder, parts)
        parts.texts[RECORD_JSON] = record.model_dump_json(indent=2)
        target = folder / bundle_name(record)
        await asyncio.to_thread(_write_zip, target, parts)
    except BaseException:
        await asyncio.to_thread(shutil.rmtree, folder, True)
        raise
    return target


def discard(bundle: Path) -> None:
    """Remove the bundle's temporary directory (blocking: a background task after sending)."""
    shutil.rmtree(bundle.parent, ignore_errors=True)
