from __future__ import annotations

from fastapi import APIRouter
from pydantic import BaseModel

from servodesk import __version__
from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import ServicesDep
from servodesk.loop_watch import LoopLag
from servodesk.models.bus import BusStatus
from servodesk.storage.usage import DataUsage

router = APIRouter(tags=["health"], route_class=AuditedRoute)


class Health(BaseModel):
    status: str
    version: str
    bus: BusStatus
    loop: LoopLag
    data: DataUsage  # the data directory: what it holds, its quotas, its disk's free space


@router.get("/health")
async def health(services: ServicesDep) -> Health:
    return Health(
        status="ok",
        version=__version__,
        bus=services.bus.status(),
        loop=services.loop_watch.lag(),
        data=await services.usage.usage(),
    )
