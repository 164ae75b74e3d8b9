"""Read and write any object-dictionary entry; "upload all" as a cancellable job."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Query

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import Index, NodeId, ServicesDep, Subindex, parse_hex
from servodesk.api.errors import NODE_ERRORS
from servodesk.models import Job, SdoValue, SdoWrite

router = APIRouter(tags=["sdo"], responses=NODE_ERRORS, route_class=AuditedRoute)


@router.get("/nodes/{node}/sdo/{index}/{subindex}")
async def read_entry(
    node: NodeId, index: Index, subindex: Subindex, services: ServicesDep
) -> SdoValue:
    return await services.sdo.read(
        node,
        parse_hex(index, maximum=0xFFFF, what="index"),
        parse_hex(subindex, maximum=0xFF, what="sub-index"),
    )


@router.put("/nodes/{node}/sdo/{index}/{subindex}")
async def write_entry(
    node: NodeId, index: Index, subindex: Subindex, body: SdoWrite, services: ServicesDep
) -> SdoValue:
    return await services.sdo.write(
        node,
        parse_hex(index, maximum=0xFFFF, what="index"),
        parse_hex(subindex, maximum=0xFF, what="sub-index"),
        body.value,
        size=body.size,
    )


@router.post("/nodes/{node}/upload-all")
async def upload_all(node: NodeId, services: ServicesDep) -> Job:
    return services.jobs.start_upload_all(node)


@router.get("/jobs/{job_id}")
async def get_job(
    job_id: str,
    services: ServicesDep,
    since: Annotated[int, Query(ge=0, description="only results from this position on")] = 0,
) -> Job:
    return services.jobs.get(job_id, since)


@router.delete("/jobs/{job_id}")
async def cancel_job(job_id: str, services: ServicesDep) -> Job:
    return await services.jobs.cancel(job_id)
