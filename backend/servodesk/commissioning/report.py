"""The hand-over report of commissioning records: one axis, or every axis of a machine, as a
self-contained HTML page (inline CSS, plots as inline SVG, nothing fetched) and as a PDF
made from that page by WeasyPrint.

What goes in is gathered on the loop from the services (record, PDOs, faults, audit, capture
samples read in a worker thread); the template (templates/report.html.j2) only lays it out.
PDF layout is CPU work of about a second per few pages: it runs in a worker thread, one at
a time, never on the event loop.

Languages: English (`en`, the default) or Simplified Chinese (`zh-CN`). Every word the report
writes itself comes from `words` (report_words.py); what users typed (titles, names, notes,
reasons) and what the drive or record stored (values, device and fault names, evidence) is
shown as stored, never translated."""

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
from servodesk.commissioning.report_words import EN, Lang, Words, words_for
from servodesk.errors import ServodeskError
from servodesk.models.commissioning import CommissioningRecord

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
STATUS_WORDS = {s: EN.status(s) for s in ("to_do", "done", "failed", "skipped")}  # English

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
    state: str = ""  # the status key ("to_do"): the badge's colour in any language

    def __post_init__(self) -> None:
        self.state = self.state or self.status.replace(" ", "_")


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
    status: str = ""  # the record's status in words

    def __post_init__(self) -> None:
        self.status = self.status or EN.status(self.record.status)


def _labels(sources: ReportSources, node: int) -> dict[str, str]:
    """The catalogue's labels by object ("2006:08" → "Maximum speed (最大转速限制)")."""
    try:
        data = sources.registry.profile_data(node)
    except ServodeskError:
        return {}
    if data is None:
        return {}
    return {f"{p.object[0]:04X}:{p.object[1]:02X}": p.label for p in data.parameters}


def _identity(record: CommissioningRecord, w: Words) -> list[tuple[str, str]]:
    ident = record.identity
    rows = [
        (w("id.node"), str(record.node)),
        (w("id.name"), ident.name or "—"),
        (w("id.vendor"), tables.cell("vendor_id", ident.vendor_id, words=w)),
        (w("id.product"), tables.cell("product_code", ident.product_code, words=w)),
        (w("id.revision"), tables.cell("revision", ident.revision, words=w)),
        (w("id.serial"), tables.cell("serial", ident.serial, words=w)),
        (w("id.hardware"), ident.hardware_version or "—"),
        (w("id.firmware"), ident.software_version or "—"),
        (w("id.device_type"), tables.cell("device_type", ident.device_type, words=w)),
        (w("id.profile"), f"{ident.profile_label} ({ident.profile})"),
        (w("id.dictionary"), f"{ident.od_filename} ({ident.od_source})"),
        (w("id.supported"), ", ".join(ident.supported_modes or []) or w("unknown")),
        (w("id.chosen"), ", ".join(record.modes) or w("none")),
    ]
    return rows


async def _plot(sources: ReportSources, capture_id: int, title: str, w: Words) -> Markup | str:
    """The capture's SVG, or a line saying why there is none."""
    try:
        capture = await sources.scope.get(capture_id)
        samples = sources.scope.store.samples_path(capture_id)
        series = await asyncio.to_thread(capture_series, capture, samples, words=w)
    except (ServodeskError, OSError) as error:
        return w("plot.failed", id=capture_id, error=error)
    if not series:
        return w("plot.empty", id=capture_id)
    if capture.name:
        name = w("plot.named", title=title, id=capture_id, name=capture.name)
    else:
        name = w("plot.title", title=title, id=capture_id)
    return Markup(svg_plot(series, name))  # every text in it is escaped by svg_plot


async def _pdo_table(
    sources: ReportSources, node: int, w: Words
) -> tuple[tables.Table | None, str | None]:
    try:
        pdos = await sources.pdos.cached(node)
    except ServodeskError as error:
        return None, w("pdos.unread", error=error)
    columns = ("pdo", "cob_id", "valid", "transmission", "event_timer", "mapping")
    table = tables.Table("", [w(f"col.{c}") for c in columns])
    for pdo in pdos:
        said = w.transmission(pdo.transmission_type, pdo.direction)
        mapping = "; ".join(
            w("pdo.mapped", object=f"{m.index:04X}h:{m.subindex:02X}", name=m.name or "",
              bits=m.bits).replace("  ", " ")
            for m in pdo.mapping
        )  # fmt: skip
        table.rows.append(
            [
                f"{pdo.kind.upper()}{pdo.number}",
                f"{pdo.cob_id:03X}h",
                w.yes_no(pdo.valid),
                w("pdo.transmission", type=pdo.transmission_type, words=said),
                f"{pdo.event_timer_ms} ms" if pdo.event_timer_ms else "—",
                mapping or "—",
            ]
        )
    return table, None


async def _faults(sources: ReportSources, record: CommissioningRecord, w: Words) -> tables.Table:
    columns = ("time", "code", "source", "fault", "check", "state")
    table = tables.Table(w("table.faults"), [w(f"col.{c}") for c in columns])
    history = await sources.faults.node_faults(record.node, FAULT_LIMIT)
    for fault in sorted(history.history, key=lambda f: f.time):
        if fault.time < record.created:
            continue
        manual = fault.name_zh and fault.name_zh_source == "manual"  # the source's words only
        name = fault.name_en + (f" ({fault.name_zh})" if manual else "")
        state = " → ".join(s for s in (fault.state_before, fault.state_after) if s)
        row = [
            w.when(fault.time),
            fault.code_hex,
            fault.source,
            name,
            fault.check or "",
            state,
        ]
        table.rows.append(row)
    return table


async def _audit(sources: ReportSources, record: CommissioningRecord, w: Words) -> tables.Table:
    from servodesk.audit.store import AuditFilter

    rows = await sources.audit.entries(
        AuditFilter(node=record.node, since=record.created, limit=AUDIT_LIMIT)
    )
    columns = ("id", "time", "user_role", "action", "what", "old_new", "result")
    table = tables.Table(w("table.audit"), [w(f"col.{c}") for c in columns])
    for row in sorted(rows, key=lambda r: r.id):
        change = (
            ""
            if row.old is None and row.new is None
            else f"{tables.cell('old', row.old, words=w)} → {tables.cell('new', row.new, words=w)}"
        )
        result = row.result + (f" ({row.abort_code})" if row.abort_code else "")
        table.rows.append(
            [f"#{row.id}", w.when(row.time), w("user_role", user=row.user, role=row.role),
             row.action, row.what, change, result]
        )  # fmt: skip
    return table


async def axis_view(
    sources: ReportSources, record: CommissioningRecord, lang: Lang = "en"
) -> AxisView:
    w = words_for(lang)
    labels = _labels(sources, record.node)
    notes: list[str] = []
    steps: list[StepView] = []
    for step in record.steps:
        title = w.step_title(step.key, step.title)
        step_tables = tables.evidence_tables(step.key, step.evidence, labels, w)
        figures = tables.figures_table(step.figures, w)
        if figures is not None:
            step_tables.insert(0, figures)
        plots: list[Markup] = []
        for capture_id in tables.capture_ids(step.evidence):
            plot = await _plot(sources, capture_id, title, w)
            if isinstance(plot, Markup):
                plots.append(plot)
            else:
                notes.append(w("note", title=title, text=plot))
        steps.append(
            StepView(
                key=step.key,
                title=title,
                status=w.status(step.status),
                by=step.by or "",
                at=w.when(step.at),
                reason=step.reason or "",
                tables=step_tables,
                plots=plots,
                state=step.status,
            )
        )
    pdos, pdo_note = await _pdo_table(sources, record.node, w)
    if pdo_note:
        notes.append(pdo_note)
    return AxisView(
        record=record,
        heading=_heading(record, w),
        created=w.when(record.created),
        identity=_identity(record, w),
        steps=steps,
        pdos=pdos,
        faults=await _faults(sources, record, w),
        audit=await _audit(sources, record, w),
        notes=notes,
        status=w.status(record.status),
    )


def _heading(record: CommissioningRecord, w: Words) -> str:
    """The record's title, led by its node unless the title names it already (the default
    title is stored in English: "Node 1 · MDi-S1-C")."""
    named = {EN("node", node=record.node), w("node", node=record.node)}
    if any(node in record.title for node in named):
        return record.title
    return f"{w('node', node=record.node)} · {record.title}"


def report_title(records: list[CommissioningRecord], w: Words = EN) -> str:
    if len(records) == 1:
        return w("report.title", title=records[0].title)
    return w("report.machine", count=len(records))


def render_html(axes: list[AxisView], *, title: str, generated: float, lang: Lang = "en") -> str:
    """The report page (pure: the template with the gathered views) in `lang`'s words."""
    w = words_for(lang)
    return _ENV.get_template("report.html.j2").render(
        title=title, axes=axes, generated=w.when(generated), t=w
    )


async def render_pdf(html: str) -> bytes:
    """The PDF of `html`, laid out in a worker process (servodesk/report_pdf.py)."""
    return await asyncio.get_running_loop().run_in_executor(_PDF_THREAD, report_pdf.render, html)
