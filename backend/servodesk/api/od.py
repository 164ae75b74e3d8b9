"""Object dictionaries: browse a node's, upload an EDS/DCF/XDD for it, lint any file."""

from __future__ import annotations

from fastapi import APIRouter, UploadFile

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import NodeId, ServicesDep
from servodesk.api.errors import NODE_ERRORS
from servodesk.api.uploads import Upload, read_limited, upload_name
from servodesk.models.od import OdCheckResult, OdTree
from servodesk.od import ObjectDictionaryModel
from servodesk.od.parser import OdParser
from servodesk.od_view import od_check, od_tree

router = APIRouter(tags=["object dictionary"], responses=NODE_ERRORS, route_class=AuditedRoute)

MAX_OD_FILE = 8 * 1024 * 1024  # the largest real EDS files are a few hundred kB


async def _load_upload(
    parser: OdParser, file: UploadFile | str | None, node_id: int | None
) -> ObjectDictionaryModel:
    name = upload_name(file, "upload.eds")
    data = await read_limited(file, MAX_OD_FILE, name)
    # parsed in a worker process: seconds for a large file, the loop keeps serving meanwhile
    return await parser.parse(data, name, node_id=node_id)


@router.get("/nodes/{node}/od")
async def node_od(node: NodeId, services: ServicesDep) -> OdTree:
    registry = services.registry
    return od_tree(registry.od(node), registry.info(node).od_source)


@router.post("/nodes/{node}/od")
async def upload_od(node: NodeId, services: ServicesDep, file: Upload = None) -> OdTree:
    services.registry.info(node)  # an unknown node fails before the file is read
    model = await _load_upload(services.od_parser, file, node)
    await services.registry.set_od(node, model, "upload")
    return od_tree(model, "upload", with_objects=False)


@router.delete("/nodes/{node}/od")
async def reset_od(node: NodeId, services: ServicesDep) -> OdTree:
    await services.registry.reset_od(node)
    return od_tree(services.registry.od(node), "profile", with_objects=False)


@router.post("/od/check")
async def check_od(services: ServicesDep, file: Upload = None) -> OdCheckResult:
    model = await _load_upload(services.od_parser, file, None)
    return od_check(model, upload_name(file, "upload"))
