"""Parameter sets as DCF files: save from a node, load onto a node, compare three ways."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, File, Form, UploadFile
from fastapi.responses import PlainTextResponse

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import NodeId, ServicesDep
from servodesk.api.errors import CONFIRM_ERRORS, NODE_ERRORS
from servodesk.api.uploads import Upload, read_limited, upload_name
from servodesk.models.paramsets import CompareResult, DcfLoadResult

router = APIRouter(
    prefix="/nodes/{node}", tags=["parameter sets"], responses=NODE_ERRORS, route_class=AuditedRoute
)

MAX_DCF_FILE = 8 * 1024 * 1024


@router.get("/dcf", response_class=PlainTextResponse)
async def save_dcf(node: NodeId, services: ServicesDep) -> PlainTextResponse:
    text = await services.paramsets.export_dcf(node)
    profile = services.registry.info(node).profile
    filename = f"node{node}-{profile}.dcf"
    return PlainTextResponse(
        text, headers={"Content-Disposition": f'attachment; filename="{filename}"'}
    )


@router.post("/dcf", responses=CONFIRM_ERRORS)
async def load_dcf(
    node: NodeId,
    services: ServicesDep,
    file: Upload = None,
    confirm: Annotated[bool, Form(description="write a set made for another device")] = False,
) -> DcfLoadResult:
    name = upload_name(file, "upload.dcf")
    data = await read_limited(file, MAX_DCF_FILE, name)
    return await services.paramsets.load_dcf(node, data, name, confirm=confirm)


@router.post("/compare")
async def compare(
    node: NodeId,
    services: ServicesDep,
    file: Annotated[UploadFile | str | None, File()] = None,
) -> CompareResult:
    name = upload_name(file, "upload.dcf") if file is not None else "upload.dcf"
    data = await read_limited(file, MAX_DCF_FILE, name) if file is not None else None
    return await services.paramsets.compare(node, data, name)
