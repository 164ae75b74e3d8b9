"""Raw-frame recording of the live bus (BLF, ASC, candump .log, MF4) through python-can's
writers."""

from __future__ import annotations

import dataclasses

from fastapi import APIRouter
from fastapi.responses import FileResponse
from pydantic import BaseModel

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import ServicesDep
from servodesk.api.errors import _error
from servodesk.events.bus import EventKind, event
from servodesk.events.texts import say
from servodesk.logs.recording import RecordingFormat, RecordingStatus
from servodesk.models.base import RequestBody

router = APIRouter(prefix="/recording", tags=["recording"], route_class=AuditedRoute)

MEDIA = {
    RecordingFormat.BLF: "application/octet-stream",
    RecordingFormat.ASC: "text/plain",
    RecordingFormat.LOG: "text/plain",
    RecordingFormat.MF4: "application/octet-stream",
}


class RecordingStart(RequestBody):
    format: RecordingFormat = RecordingFormat.BLF


class RecordingInfo(BaseModel):
    active: bool
    format: RecordingFormat | None
    file: str | None
    since: float | None
    frames: int
    dropped: int


def _info(status: RecordingStatus) -> RecordingInfo:
    return RecordingInfo(**dataclasses.asdict(status))


@router.get("")
async def recording_status(services: ServicesDep) -> RecordingInfo:
    return _info(services.recorder.status())


@router.post("")
async def start_recording(body: RecordingStart, services: ServicesDep) -> RecordingInfo:
    """Start recording every frame received (a running recording goes on, in its format)."""
    was = services.recorder.status().active
    status = await services.recorder.start(body.format)
    if not was:
        services.events.publish(
            event(EventKind.RECORDING, None, say("event.recording_started", file=str(status.file)))
        )
    return _info(status)


@router.delete(
    "",
    response_class=FileResponse,
    responses={
        409: _error("No recording is running (recording_not_running)"),
        200: {
            "description": "the recorded file",
            "content": {
                "application/octet-stream": {"schema": {"type": "string", "format": "binary"}},
                "text/plain": {"schema": {"type": "string"}},
            },
        },
    },
)
async def stop_recording(services: ServicesDep) -> FileResponse:
    """Stop, close the file and download it (it stays in `<data_dir>/recordings`)."""
    path, status = await services.recorder.stop()
    services.events.publish(
        event(
            EventKind.RECORDING,
            None,
            say("event.recording_stopped", frames=status.frames, file=path.name),
            {"frames": status.frames, "dropped": status.dropped},
        )
    )
    media = MEDIA[RecordingFormat(status.format)] if status.format else "application/octet-stream"
    return FileResponse(path, media_type=media, filename=path.name)
