"""Bus connection: connect, disconnect, reconnect, status, available interfaces."""

from __future__ import annotations

from fastapi import APIRouter

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import ServicesDep
from servodesk.api.errors import BUS_ERRORS, CONNECT_ERRORS
from servodesk.bus.interfaces import INTERFACES
from servodesk.models.bus import BusConfig, BusStatus, InterfaceInfo
from servodesk.models.network import SyncConfig

router = APIRouter(prefix="/bus", tags=["bus"], responses=BUS_ERRORS, route_class=AuditedRoute)


@router.get("")
async def bus_status(services: ServicesDep) -> BusStatus:
    return services.bus.status()


@router.post("/connect", responses=CONNECT_ERRORS)
async def connect(config: BusConfig, services: ServicesDep) -> BusStatus:
    return await services.bus.connect(config)


@router.post("/disconnect")
async def disconnect(services: ServicesDep) -> BusStatus:
    return await services.bus.disconnect()


@router.post("/reconnect")
async def reconnect(services: ServicesDep) -> BusStatus:
    return await services.bus.reconnect()


@router.get("/interfaces")
async def interfaces() -> list[InterfaceInfo]:
    return list(INTERFACES)


sync_router = APIRouter(
    prefix="/sync", tags=["bus"], responses=BUS_ERRORS, route_class=AuditedRoute
)


@sync_router.get("")
async def sync_status(services: ServicesDep) -> SyncConfig:
    return services.sync.get()


@sync_router.put("")
async def set_sync(config: SyncConfig, services: ServicesDep) -> SyncConfig:
    return await services.sync.set(config.period_us)
