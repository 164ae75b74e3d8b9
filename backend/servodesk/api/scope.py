"""The live scope: plan a capture, start it, follow it, stop it, export it (docs/scope.md)."""

from __future__ import annotations

import asyncio
from pathlib import Path as FilePath
from typing import Annotated

from fastapi import APIRouter, Path, Query, Response
from fastapi.responses import FileResponse

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import ServicesDep
from servodesk.api.errors import NODE_ERRORS, PDO_APPLY_ERRORS, _error
from servodesk.errors import InvalidValueError, StateConflictError
from servodesk.models.scope import (
    ACTIVE_STATES,
    Capture,
    CaptureRequest,
    ExportFormat,
    ExportLayout,
    Measurement,
    ScopePlan,
    Trace,
)
from servodesk.scope import export as exports
from servodesk.scope import measure as measures
from servodesk.scope.samples import is_complete

router = APIRouter(prefix="/scope", tags=["scope"], route_class=AuditedRoute)

CaptureId = Annotated[int, Path(ge=1, le=2**53, description="capture id")]

Responses = dict[int | str, dict[str, object]]
NOT_FOUND: Responses = {404: _error("No such capture (capture_not_found)")}
START_ERRORS: Responses = {
    **NODE_ERRORS,
    **PDO_APPLY_ERRORS,
    409: _error(
        "scope_busy: another capture is arming, armed or running; or the scope's TPDOs could "
        "not be written (pdo_apply_failed, the previous PDOs restored); or an SDO abort"
    ),
}
FILE: Responses = {
    200: {
        "description": "the exported capture",
        "content": {
            "text/csv": {"schema": {"type": "string"}},
            "application/octet-stream": {"schema": {"type": "string", "format": "binary"}},
        },
    },
    409: _error("The capture is still armed or running (capture_recording)"),
}


@router.post("/plan", responses=START_ERRORS)
async def plan_capture(body: CaptureRequest, services: ServicesDep) -> ScopePlan:
    """What a capture would do, without starting it: each signal's source (TPDO or SDO
    polling, and why) and the bus load at the chosen SYNC period (refused above 100 %)."""
    return await services.scope.plan(body)


@router.post("/captures", responses=START_ERRORS)
async def start_capture(body: CaptureRequest, services: ServicesDep) -> Capture:
    """Set the bus up (SYNC, the scope's TPDOs in free slots, nodes Operational) and start a
    capture. It is `arming` until the signal its trigger watches has sent a first sample (a
    condition met before would be missed), then `armed` until the trigger (free-running: at
    once), then `running`."""
    return await services.scope.start(body)


@router.get("/captures")
async def list_captures(services: ServicesDep) -> list[Capture]:
    """Every capture kept, newest first (the active one with its live progress)."""
    return await services.scope.list()


@router.get("/captures/{capture_id}", responses=NOT_FOUND)
async def get_capture(capture_id: CaptureId, services: ServicesDep) -> Capture:
    return await services.scope.get(capture_id)


@router.delete(
    "/captures/{capture_id}",
    response_model=Capture,
    responses={**NOT_FOUND, 204: {"description": "the capture and its files are deleted"}},
)
async def stop_or_delete_capture(
    capture_id: CaptureId, services: ServicesDep
) -> Capture | Response:
    """An armed or running capture is stopped (its setup undone; 200 with the capture as
    kept); a finished one is deleted with its files (204)."""
    stopped = await services.scope.stop(capture_id)
    if stopped is not None:
        return stopped
    await services.scope.delete(capture_id)
    return Response(status_code=204)


@router.get(
    "/captures/{capture_id}/export",
    response_class=FileResponse,
    responses={**NOT_FOUND, **FILE},
)
async def export_capture(
    capture_id: CaptureId,
    services: ServicesDep,
    fmt: Annotated[
        ExportFormat,
        Query(alias="format", description="csv, parquet (pyarrow), mf4 (asammdf) or rrd (rerun)"),
    ] = "csv",
    layout: Annotated[
        ExportLayout,
        Query(
            description="CSV only: long (one row per sample) or wide (one row per time stamp, "
            "a column per signal)"
        ),
    ] = "long",
) -> FileResponse:
    capture = await services.scope.get(capture_id)
    path = await services.scope.export(capture_id, fmt, layout)
    name = exports.filename(capture, fmt, layout)
    return FileResponse(path, media_type=exports.content_type(fmt), filename=name)


RECORDING: Responses = {
    409: _error("The capture is still armed or running, or its samples were never finished")
}
Seconds = Annotated[float, Query(description="s from the trigger (negative before it)")]


async def _finished_samples(capture_id: int, services: ServicesDep) -> tuple[Capture, FilePath]:
    capture = await services.scope.get(capture_id)
    if capture.state in ACTIVE_STATES:
        raise StateConflictError(
            "capture_recording",
            f"capture {capture_id} is still {capture.state}: measure it when it is done",
        )
    path = services.scope.store.samples_path(capture_id)
    if not await asyncio.to_thread(is_complete, path):
        raise StateConflictError(
            "samples_incomplete", f"capture {capture_id}'s samples were never finished"
        )
    return capture, path


@router.get("/captures/{capture_id}/measure", responses={**NOT_FOUND, **RECORDING})
async def measure_capture(
    capture_id: CaptureId, services: ServicesDep, t0: Seconds, t1: Seconds
) -> Measurement:
    """Cursor A at `t0` and B at `t1` on a finished capture: per signal the value at each
    (the sample at or before it), Δvalue, and min / max / mean / count between them."""
    capture, path = await _finished_samples(capture_id, services)
    try:
        return await asyncio.to_thread(measures.measure_file, path, capture, t0, t1)
    except measures.CursorError as error:
        raise InvalidValueError(str(error)) from None


@router.get("/captures/{capture_id}/trace", responses={**NOT_FOUND, **RECORDING})
async def trace_capture(
    capture_id: CaptureId,
    services: ServicesDep,
    signal: Annotated[int, Query(ge=0, description="position in the capture's signals")] = 0,
    points: Annotated[int, Query(ge=2, le=measures.MAX_POINTS)] = 400,
) -> Trace:
    """One signal as min/max bins over the capture, for the overview the cursors sit on."""
    capture, path = await _finished_samples(capture_id, services)
    try:
        return await asyncio.to_thread(measures.trace_file, path, capture, signal, points)
    except measures.CursorError as error:
        raise InvalidValueError(str(error)) from None
