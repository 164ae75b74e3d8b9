"""Nodes on the bus: list, scan, NMT, heartbeat producer time."""

from __future__ import annotations

from fastapi import APIRouter, Response
from pydantic import BaseModel

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import NodeId, ServicesDep
from servodesk.api.errors import CONFIRM_ERRORS, NODE_ERRORS, _error
from servodesk.models.network import HeartbeatConfig, HeartbeatWrite, NmtCommandName, NmtRequest
from servodesk.models.nodes import NodeInfo, ScanRequest, ScanResult

router = APIRouter(tags=["nodes"], responses=NODE_ERRORS, route_class=AuditedRoute)


class NmtSent(BaseModel):
    sent: NmtCommandName


@router.get("/nodes")
async def list_nodes(services: ServicesDep) -> list[NodeInfo]:
    return services.registry.all()


@router.get("/nodes/{node}")
async def get_node(node: NodeId, services: ServicesDep) -> NodeInfo:
    return services.registry.info(node)


@router.delete(
    "/nodes/{node}",
    status_code=204,
    response_class=Response,
    responses={
        204: {"description": "the node is no longer listed (a scan or its boot-up adds it again)"},
        409: _error("node_online: the node answers on the bus; only a gone node is forgotten"),
    },
)
async def forget_node(node: NodeId, services: ServicesDep) -> Response:
    """Forget a node that is gone: silent, or answering at another id now (`moved_to`)."""
    await services.registry.forget(node)
    return Response(status_code=204)


@router.post("/scan")
async def scan(request: ScanRequest, services: ServicesDep) -> ScanResult:
    return await services.registry.scan(sdo_sweep=request.sdo_sweep, timeout_ms=request.timeout_ms)


@router.post("/nodes/{node}/nmt")
async def nmt(node: NodeId, request: NmtRequest, services: ServicesDep) -> NodeInfo:
    return await services.registry.nmt(node, request.command)


@router.post("/nmt")
async def nmt_broadcast(request: NmtRequest, services: ServicesDep) -> NmtSent:
    await services.registry.nmt_broadcast(request.command)
    return NmtSent(sent=request.command)


@router.get("/nodes/{node}/heartbeat")
async def heartbeat(node: NodeId, services: ServicesDep) -> HeartbeatConfig:
    return HeartbeatConfig(producer_ms=await services.registry.heartbeat(node))


@router.put("/nodes/{node}/heartbeat", responses=CONFIRM_ERRORS)
async def set_heartbeat(
    node: NodeId, config: HeartbeatWrite, services: ServicesDep
) -> HeartbeatConfig:
    ms = await services.registry.set_heartbeat(node, config.producer_ms, confirm=config.confirm)
    return HeartbeatConfig(producer_ms=ms)
