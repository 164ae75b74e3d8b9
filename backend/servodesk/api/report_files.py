"""The commissioning report and bundle as HTTP answers (the routes are in commissioning.py):
which records a machine report holds, and the HTML / PDF / zip responses."""

from __future__ import annotations

import time

from fastapi import Response
from fastapi.responses import FileResponse, HTMLResponse
from starlette.background import BackgroundTask

from servodesk.commissioning import bundle, report
from servodesk.commissioning.report_words import Lang, words_for
from servodesk.errors import NotFoundError
from servodesk.models.commissioning import CommissioningRecord
from servodesk.services import Services


def sources(services: Services) -> report.ReportSources:
    return report.ReportSources(
        registry=services.registry,
        pdos=services.pdos,
        faults=services.faults,
        audit=services.audit,
        scope=services.scope,
        paramsets=services.paramsets,
    )


def numbers(text: str | None) -> list[int]:
    """ "1,2,3" → [1, 2, 3], each once (the query's pattern has checked the digits)."""
    return list(dict.fromkeys(int(n) for n in text.split(","))) if text else []


async def machine_records(
    services: Services, ids: list[int], nodes: list[int]
) -> list[CommissioningRecord]:
    """The records of a machine report, by node: the listed records, else the latest record of
    each listed node, else the latest record of every node that has one."""
    if ids:
        records = [await services.commissioning.get(i) for i in ids]
        return sorted(records, key=lambda r: (r.node, r.id))
    latest: dict[int, CommissioningRecord] = {}
    for record in await services.commissioning.list():  # newest first
        latest.setdefault(record.node, record)
    if nodes:
        absent = [n for n in nodes if n not in latest]
        if absent:
            raise NotFoundError(
                "commissioning_not_found",
                f"no commissioning record for node(s) {', '.join(map(str, absent))}: make one "
                "with POST /api/nodes/{node}/commissioning",
            )
        return [latest[n] for n in sorted(nodes)]
    if not latest:
        raise NotFoundError(
            "commissioning_not_found",
            "no commissioning records yet: make one with POST /api/nodes/{node}/commissioning",
        )
    return [latest[n] for n in sorted(latest)]


def _disposition(name: str) -> dict[str, str]:
    return {"Content-Disposition": f'attachment; filename="{name}"'}


async def answer(
    services: Services,
    records: list[CommissioningRecord],
    fmt: report.ReportFormat,
    name: str,
    lang: Lang = "en",
) -> Response:
    """The report of `records` as `fmt` in `lang`; `name` is the download's name without its
    suffix. zip: one record's bundle, its report.html and report.pdf in `lang`."""
    src = sources(services)
    axes = [await report.axis_view(src, record, lang) for record in records]
    title = report.report_title(records, words_for(lang))
    html = report.render_html(axes, title=title, generated=time.time(), lang=lang)
    if fmt == "html":
        return HTMLResponse(html)
    pdf = await report.render_pdf(html)
    if fmt == "pdf":
        return Response(pdf, media_type="application/pdf", headers=_disposition(f"{name}.pdf"))
    path = await bundle.build_bundle(src, records[0], html, pdf)
    return FileResponse(
        path,
        media_type="application/zip",
        filename=path.name,
        background=BackgroundTask(bundle.discard, path),
    )
