"""Offline CAN log analysis: upload a log, page its events, export them (docs/logs.md)."""

from __future__ import annotations

import contextlib
import dataclasses
from pathlib import Path
from typing import Annotated, Any

from fastapi import APIRouter, File, Form, Query, UploadFile
from fastapi.responses import FileResponse, Response
from pydantic import BaseModel, Field
from starlette.background import BackgroundTask

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import ServicesDep
from servodesk.api.errors import _error
from servodesk.api.uploads import Upload, read_limited, upload_name
from servodesk.logs.events import Event
from servodesk.logs.export import ExportFormat
from servodesk.logs.service import EXPORT_TYPES, event_data
from servodesk.logs.store import LogResult
from servodesk.services import Services

router = APIRouter(prefix="/logs", tags=["logs"], route_class=AuditedRoute)

FIRST_PAGE = 500
MAX_DCF = 8 * 1024 * 1024
LogId = Annotated[str, Query()]
NOT_FOUND: dict[int | str, dict[str, Any]] = {404: _error("No decoded log with this id")}


class LogEvent(BaseModel):
    seq: int
    time: float
    frame: int
    kind: str
    node: int | None
    text: str
    index: int | None
    subindex: int | None
    code: int | None
    data: Any = Field(description="detail: a Fault for emcy, values by IIII:SS for pdo, …")
    polling: bool = Field(
        default=False,
        description="an SDO read repeated at a steady period (a poll loop such as ServoDesk's"
        " own Drive page); hidden by `hide_polling`",
    )


class LogEventPage(BaseModel):
    events: list[LogEvent]
    next: int | None = Field(description="pass as `since` for the next page; null at the end")


class DecodedLog(LogEventPage):
    id: str
    name: str
    summary: list[str]
    stats: dict[str, Any]


def _page(events: list[Event], limit: int) -> LogEventPage:
    rows = [LogEvent(**{**e.as_dict(), "data": event_data(e)}) for e in events]
    return LogEventPage(events=rows, next=events[-1].seq + 1 if len(events) == limit else None)


@router.post("/decode")
async def decode_log(
    services: ServicesDep,
    file: Upload = None,
    dcf: Annotated[
        UploadFile | str | None, File(description="optional DCF: PDO mappings, identity")
    ] = None,
    profiles: Annotated[
        str | None,
        Form(
            description="which drive a node is, for nodes whose identity the log does not"
            ' show: "1=mdi-s1c, 2=kinco" (profiles mdi-s1c, kinco, cia402)'
        ),
    ] = None,
) -> DecodedLog:
    limit = services.settings.log_upload_max_mb * 1024 * 1024
    name = upload_name(file, "upload.log")
    data = await read_limited(file, limit, name)
    dcf_part: tuple[str, bytes] | None = None
    if dcf is not None:
        dcf_name = upload_name(dcf, "upload.dcf")
        dcf_part = (dcf_name, await read_limited(dcf, MAX_DCF, dcf_name))
    result = await services.logs.decode(name, data, dcf_part, profiles)
    services.usage.forget()  # a new file under logs/
    return await _decoded(services, result)


async def _decoded(services: Services, result: LogResult) -> DecodedLog:
    """A decode's answer: its summary and totals with the first page of its events."""
    first = _page(await services.logs.events(result.id, 0, FIRST_PAGE), FIRST_PAGE)
    return DecodedLog(
        id=result.id,
        name=result.name,
        summary=result.summary,
        stats=result.stats,
        events=first.events,
        next=first.next,
    )


class KeptLogInfo(BaseModel):
    """A decoded log kept on the server (the oldest go beyond SERVODESK_LOGS_KEEP_MB)."""

    id: str
    name: str
    size_bytes: int
    created: float = Field(description="when its decode finished (epoch s)")


@router.get("")
async def list_logs(services: ServicesDep) -> list[KeptLogInfo]:
    """The decoded logs kept, newest first."""
    return [KeptLogInfo(**dataclasses.asdict(k)) for k in await services.logs.kept()]


@router.get("/{log_id}", responses=NOT_FOUND)
async def get_log(log_id: str, services: ServicesDep) -> DecodedLog:
    """A decoded log again: its summary, totals and first page of events."""
    return await _decoded(services, await services.logs.result(log_id))


@router.delete(
    "/{log_id}",
    status_code=204,
    response_class=Response,
    responses={**NOT_FOUND, 204: {"description": "the decoded log is deleted"}},
)
async def delete_log(log_id: str, services: ServicesDep) -> Response:
    """Delete a decoded log (its events and exports with it); the uploaded file was never
    kept."""
    await services.logs.delete(log_id)
    services.usage.forget()
    return Response(status_code=204)


@router.get("/{log_id}/events", responses=NOT_FOUND)
async def log_events(
    log_id: str,
    services: ServicesDep,
    since: Annotated[int, Query(ge=0, description="first event seq")] = 0,
    limit: Annotated[int, Query(ge=1, le=10_000)] = FIRST_PAGE,
    hide_polling: Annotated[
        bool,
        Query(
            description="leave out SDO reads repeated at a steady period (the tool's own"
            " polling and any other poll loop): the same object of a node read a third time"
            " and on, each interval within half a period of the one before, period ≤ 2 s"
        ),
    ] = False,
) -> LogEventPage:
    events = await services.logs.events(log_id, since, limit, hide_polling=hide_polling)
    return _page(events, limit)


@router.get(
    "/{log_id}/export",
    response_class=FileResponse,
    responses={
        **NOT_FOUND,
        200: {
            "description": "every event of the log as CSV, JSON lines or Parquet",
            "content": {
                t: {"schema": {"type": "string", "format": "binary"}} for t in EXPORT_TYPES.values()
            },
        },
    },
)
async def export_log(
    log_id: str,
    services: ServicesDep,
    format: ExportFormat = ExportFormat.CSV,  # the documented query name
) -> FileResponse:
    if format is ExportFormat.TEXT:
        format = ExportFormat.CSV  # not offered: the API exports tables
    path = await services.logs.export(log_id, format)
    result = await services.logs.result(log_id)
    stem = Path(result.name).stem or "log"
    return FileResponse(
        path,
        media_type=EXPORT_TYPES[format],
        filename=f"{stem}-events.{'jsonl' if format is ExportFormat.JSON else format.value}",
        background=BackgroundTask(_unlink, path),
    )


def _unlink(path: Path) -> None:
    with contextlib.suppress(OSError):
        path.unlink()
