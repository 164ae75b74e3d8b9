"""Faults: live and stored, the drive's own history (1003h), fault reset (docs/api.md)."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Body, Query

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import NodeId, ServicesDep
from servodesk.api.drive import ClientDep
from servodesk.api.errors import CONFIRM_ERRORS, MOTION_ERRORS, NODE_ERRORS
from servodesk.models.faults import (
    ActiveFaults,
    ConfirmBody,
    DeviceHistory,
    DeviceHistoryCleared,
    FaultResetResult,
    NodeFaults,
)

router = APIRouter(tags=["faults"], route_class=AuditedRoute)


@router.get("/nodes/{node}/faults")
async def node_faults(
    node: NodeId,
    services: ServicesDep,
    limit: Annotated[int, Query(ge=1, le=10_000, description="newest history entries")] = 100,
    all_buses: Annotated[
        bool,
        Query(
            description="also the faults stored from other buses (another server sharing this "
            "data directory, a bus connected before); default: the connected bus's only"
        ),
    ] = False,
) -> NodeFaults:
    return await services.faults.node_faults(node, limit, all_buses=all_buses)


@router.get("/faults/active")
async def active_faults(services: ServicesDep) -> ActiveFaults:
    return ActiveFaults(faults=services.faults.all_active())


@router.post("/nodes/{node}/faults/reset", responses=MOTION_ERRORS)
async def fault_reset(node: NodeId, client: ClientDep, services: ServicesDep) -> FaultResetResult:
    """Like `/drive/fault-reset`, it passes the controller lease: another client's reset of a
    drive someone controls answers 409 held_by_other (name yourself with X-Client-Id)."""
    await services.safety.authorize(node, client)
    return await services.faults.reset(node)


@router.get("/nodes/{node}/faults/device-history", responses=NODE_ERRORS)
async def device_history(node: NodeId, services: ServicesDep) -> DeviceHistory:
    return await services.faults.device_history(node)


@router.delete("/nodes/{node}/faults/device-history", responses={**NODE_ERRORS, **CONFIRM_ERRORS})
async def clear_device_history(
    node: NodeId,
    services: ServicesDep,
    body: Annotated[ConfirmBody | None, Body()] = None,
) -> DeviceHistoryCleared:
    confirm = body.confirm if body is not None else False
    return await services.faults.clear_device_history(node, confirm=confirm)
