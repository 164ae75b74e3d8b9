"""Object dictionaries: browse a node's, upload an EDS/DCF/XDD for it, lint any file."""

from __future__ import annotations

from fastapi import APIRouter, UploadFile

from servodesk.api.deps import NodeId, ServicesDep
from servodesk.api.errors import NODE_ERRORS
from servodesk.errors import InvalidValueError
from servodesk.models import OdCheckResult, OdTree
from servodesk.od import ObjectDictionaryModel, OdImportError, load_od_bytes
from servodesk.od_view import od_check, od_tree

router = APIRouter(tags=["object dictionary"], responses=NODE_ERRORS)

MAX_OD_FILE = 8 * 1024 * 1024  # the largest real EDS files are a few hundred kB


async def _load_upload(file: UploadFile, node_id: int | None) -> ObjectDictionaryModel:
    data = await file.read(MAX_OD_FILE + 1)
    if len(data) > MAX_OD_FILE:
        raise InvalidValueError(f"{file.filename}: larger than {MAX_OD_FILE // 1024} kB")
    try:
        return load_od_bytes(data, file.filename or "upload.eds", node_id=node_id)
    except OdImportError as error:
        raise InvalidValueError(f"{file.filename}: {error}") from error


@router.get("/nodes/{node}/od")
async def node_od(node: NodeId, services: ServicesDep) -> OdTree:
    registry = services.registry
    return od_tree(registry.od(node), registry.info(node).od_source)


@router.post("/nodes/{node}/od")
async def upload_od(node: NodeId, file: UploadFile, services: ServicesDep) -> OdTree:
    model = await _load_upload(file, node)
    services.registry.set_od(node, model, "upload")
    return od_tree(model, "upload", with_objects=False)


@router.delete("/nodes/{node}/od")
async def reset_od(node: NodeId, services: ServicesDep) -> OdTree:
    services.registry.reset_od(node)
    return od_tree(services.registry.od(node), "profile", with_objects=False)


@router.post("/od/check")
async def check_od(file: UploadFile) -> OdCheckResult:
    model = await _load_upload(file, None)
    return od_check(model, file.filename or "upload")
