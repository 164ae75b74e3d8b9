"""The live scope: plan a capture, start it, follow it, stop it, export it (docs/scope.md)."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path, Query, Response
from fastapi.responses import FileResponse

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import ServicesDep
from servodesk.api.errors import NODE_ERRORS, PDO_APPLY_ERRORS, _error
from servodesk.scope import export as exports
from servodesk.scope_models import Capture, CaptureRequest, ExportFormat, ScopePlan

router = APIRouter(prefix="/scope", tags=["scope"], route_class=AuditedRoute)

CaptureId = Annotated[int, Path(ge=1, le=2**53, description="capture id")]

Responses = dict[int | str, dict[str, object]]
NOT_FOUND: Responses = {404: _error("No such capture (capture_not_found)")}
START_ERRORS: Responses = {
    **NODE_ERRORS,
    **PDO_APPLY_ERRORS,
    409: _error(
        "scope_busy: another capture is armed or running; or the scope's TPDOs could not be "
        "written (pdo_apply_failed, the previous PDOs restored); or an SDO abort"
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
    capture: `running` at once when free-running, else `armed` until the trigger."""
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
) -> FileResponse:
    capture = await services.scope.get(capture_id)
    path = await services.scope.export(capture_id, fmt)
    return FileResponse(
        path, media_type=exports.content_type(fmt), filename=exports.filename(capture, fmt)
    )
