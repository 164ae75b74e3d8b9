"""The hand-over report of commissioning records: one axis, or every axis of a machine, as a
self-contained HTML page (inline CSS, plots as inline SVG, nothing fetched) and as a PDF
made from that page by WeasyPrint.

What goes in is gathered on the loop from the services (record, PDOs, faults, audit, capture
samples read in a worker thread); the template (templates/report.html.j2) only lays it out.
PDF layout is CPU work of about a second per few pages: it runs in a worker thread, one at
a time, never on the event loop."""

from __future__ import annotations

import asyncio
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal

import jinja2
from markupsafe import Markup

from servodesk import report_pdf
from servodesk.commissioning import report_tables as tables
from servodesk.commissioning.report_plot import capture_series, svg_plot
from servodesk.errors import ServodeskError
from servodesk.models.commissioning import CommissioningRecord
from servodesk_protocol.pdo import transmission_words

if TYPE_CHECKING:
    from servodesk.audit import AuditLog
    from servodesk.faults.service import FaultService
    from servodesk.nodes.registry import NodeRegistry
    from servodesk.params.paramsets import ParamSetService
    from servodesk.pdo.service import PdoService
    from servodesk.scope.service import ScopeService

ReportFormat = Literal["html", "pdf", "zip"]
MachineFormat = Literal["html", "pdf"]
AUDIT_LIMIT = 2000  # audit entries shown per axis (the bundle's CSV has all of them)
FAULT_LIMIT = 1000
STATUS_WORDS = {"to_do": "to do", "done": "done", "failed": "failed", "skipped": "skipped"}

_ENV = jinja2.Environment(
    loader=jinja2.PackageLoader("servodesk.commissioning", "templates"),
    autoescape=True,  # every record value is user text: names, titles, reasons
    undefined=jinja2.StrictUndefined,
    trim_blocks=True,
    lstrip_blocks=True,
)
# one PDF at a time; this thread waits for the worker process that lays it out
_PDF_THREAD = ThreadPoolExecutor(max_workers=1, thread_name_prefix="report-pdf")


@dataclass
class ReportSources:
    """The services a report reads (the API hands in the app's)."""

    registry: NodeRegistry
    pdos: PdoService
    faults: FaultService
    audit: AuditLog
    scope: ScopeService
    paramsets: ParamSetService


@dataclass
class StepView:
    key: str
    title: str
    status: str
    by: str
    at: str
    reason: str
    tables: list[tables.Table]
    plots: list[Markup]


@dataclass
class AxisView:
    record: CommissioningRecord
    heading: str
    created: str
    identity: list[tuple[str, str]]
    steps: list[StepView]
    pdos: tables.Table | None
    faults: tables.Table
    audit: tables.Table
    notes: list[str] = field(default_factory=list)


def _labels(sources: ReportSources, node: int) -> dict[str, str]:
    """The catalogue's labels by object ("2006:08" → "Maximum speed (最大转速限制)")."""
    try:
        data = sources.registry.profile_data(node)
    except ServodeskError:
        return {}
    if data is None:
        return {}
    return {f"{p.object[0]:04X}:{p.object[1]:02X}": p.label for p in data.parameters}


def _identity(record: CommissioningRecord) -> list[tuple[str, str]]:
    ident = record.identity
    rows = [
        ("Node", str(record.node)),
        ("Device name (1008h)", ident.name or "—"),
        ("Vendor id (1018h:01)", tables.cell("vendor_id", ident.vendor_id)),
        ("Product code (1018h:02)", tables.cell("product_code", ident.product_code)),
        ("Revision (1018h:03)", tables.cell("revision", ident.revision)),
        ("Serial (1018h:04)", tables.cell("serial", ident.serial)),
        ("Hardware (1009h)", ident.hardware_version or "—"),
        ("Firmware (100Ah)", ident.software_version or "—"),
        ("Device type (1000h)", tables.cell("device_type", ident.device_type)),
        ("Profile", f"{ident.profile_label} ({ident.profile})"),
        ("Dictionary", f"{ident.od_filename} ({ident.od_source})"),
        ("Supported modes (6502h)", ", ".join(ident.supported_modes or []) or "unknown"),
        ("Chosen modes", ", ".join(record.modes) or "none"),
    ]
    return rows


async def _plot(sources: ReportSources, capture_id: int, title: str) -> Markup | str:
    """The capture's SVG, or a line saying why there is none."""
    try:
        capture = await sources.scope.get(capture_id)
        samples = sources.scope.store.samples_path(capture_id)
        series = await asyncio.to_thread(capture_series, capture, samples)
    except (ServodeskError, OSError) as error:
        return f"capture {capture_id}: no plot ({error})"
    if not series:
        return f"capture {capture_id}: no samples to plot"
    name = f"{title}: capture {capture_id}" + (f" ({capture.name})" if capture.name else "")
    return Markup(svg_plot(series, name))  # every text in it is escaped by svg_plot


async def _pdo_table(sources: ReportSources, node: int) -> tuple[tables.Table | None, str | None]:
    try:
        pdos = await sources.pdos.cached(node)
    except ServodeskError as error:
        return None, f"PDOs not read: {error}"
    table = tables.Table("", ["PDO", "COB-ID", "Valid", "Transmission", "Event timer", "Mapping"])
    for pdo in pdos:
        words = transmission_words(pdo.transmission_type, pdo.direction)
        mapping = "; ".join(
            f"{m.index:04X}h:{m.subindex:02X} {m.name or ''} ({m.bits} bit)".replace("  ", " ")
            for m in pdo.mapping
        )
        table.rows.append(
            [
                f"{pdo.kind.upper()}{pdo.number}",
                f"{pdo.cob_id:03X}h",
                "yes" if pdo.valid else "no",
                f"{pdo.transmission_type} ({words})",
                f"{pdo.event_timer_ms} ms" if pdo.event_timer_ms else "—",
                mapping or "—",
            ]
        )
    return table, None


async def _faults(sources: ReportSources, record: CommissioningRecord) -> tables.Table:
    table = tables.Table("Faults", ["Time", "Code", "Source", "Fault", "Check", "State"])
    history = await sources.faults.node_faults(record.node, FAULT_LIMIT)
    for fault in sorted(history.history, key=lambda f: f.time):
        if fault.time < record.created:
            continue
        manual = fault.name_zh and fault.name_zh_source == "manual"  # the source's words only
        name = fault.name_en + (f" ({fault.name_zh})" if manual else "")
        state = " → ".join(s for s in (fault.state_before, fault.state_after) if s)
        row = [
            tables.when(fault.time),
            fault.code_hex,
            fault.source,
            name,
            fault.check or "",
            state,
        ]
        table.rows.append(row)
    return table


async def _audit(sources: ReportSources, record: CommissioningRecord) -> tables.Table:
    from servodesk.audit.store import AuditFilter

    rows = await sources.audit.entries(
        AuditFilter(node=record.node, since=record.created, limit=AUDIT_LIMIT)
    )
    table = tables.Table(
        "Audit log", ["Id", "Time", "User (role)", "Action", "What", "Old → new", "Result"]
    )
    for row in sorted(rows, key=lambda r: r.id):
        change = (
            ""
            if row.old is None and row.new is None
            else (f"{tables.cell('old', row.old)} → {tables.cell('new', row.new)}")
        )
        result = row.result + (f" ({row.abort_code})" if row.abort_code else "")
        table.rows.append(
            [f"#{row.id}", tables.when(row.time), f"{row.user} ({row.role})", row.action,
             row.what, change, result]
        )  # fmt: skip
    return table


async def axis_view(sources: ReportSources, record: CommissioningRecord) -> AxisView:
    labels = _labels(sources, record.node)
    notes: list[str] = []
    steps: list[StepView] = []
    for step in record.steps:
        step_tables = tables.evidence_tables(step.key, step.evidence, labels)
        figures = tables.figures_table(step.figures)
        if figures is not None:
            step_tables.insert(0, figures)
        plots: list[Markup] = []
        for capture_id in tables.capture_ids(step.evidence):
            plot = await _plot(sources, capture_id, step.title)
            if isinstance(plot, Markup):
                plots.append(plot)
            else:
                notes.append(f"{step.title}: {plot}")
        steps.append(
            StepView(
                key=step.key,
                title=step.title,
                status=STATUS_WORDS[step.status],
                by=step.by or "",
                at=tables.when(step.at),
                reason=step.reason or "",
                tables=step_tables,
                plots=plots,
            )
        )
    pdos, pdo_note = await _pdo_table(sources, record.node)
    if pdo_note:
        notes.append(pdo_note)
    node = f"Node {record.node}"
    return AxisView(
        record=record,
        heading=record.title if node in record.title else f"{node} · {record.title}",
        created=tables.when(record.created),
        identity=_identity(record),
        steps=steps,
        pdos=pdos,
        faults=await _faults(sources, record),
        audit=await _audit(sources, record),
        notes=notes,
    )


def render_html(axes: list[AxisView], *, title: str, generated: float) -> str:
    """The report page (pure: the template with the gathered views)."""
    return _ENV.get_template("report.html.j2").render(
        title=title, axes=axes, generated=tables.when(generated)
    )


async def render_pdf(html: str) -> bytes:
    """The PDF of `html`, laid out in a worker process (servodesk/report_pdf.py)."""
    return await asyncio.get_running_loop().run_in_executor(_PDF_THREAD, report_pdf.render, html)
