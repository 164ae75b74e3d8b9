"""Drive parameters by their user-facing names; store/restore; node-id and bitrate changes."""

from __future__ import annotations

from fastapi import APIRouter

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import NodeId, ServicesDep
from servodesk.api.errors import CONFIRM_ERRORS, NODE_ERRORS
from servodesk.models.common import Confirm, MessageResult
from servodesk.models.nodes import (
    BitrateChange,
    BitrateChangeResult,
    BitrateOptions,
    NodeIdChange,
    NodeIdChangeResult,
    NodeIdOptions,
)
from servodesk.models.params import Param, ParamWriteRequest, ParamWriteResult

router = APIRouter(
    prefix="/nodes/{node}", tags=["parameters"], responses=NODE_ERRORS, route_class=AuditedRoute
)


@router.get("/params")
async def list_params(node: NodeId, services: ServicesDep) -> list[Param]:
    return await services.params.list(node)


@router.get("/params/{name}")
async def get_param(node: NodeId, name: str, services: ServicesDep) -> Param:
    return await services.params.get(node, name)


@router.put("/params/{name}")
async def set_param(
    node: NodeId, name: str, body: ParamWriteRequest, services: ServicesDep
) -> ParamWriteResult:
    return await services.params.set(node, name, body.value)


@router.post("/store", responses=CONFIRM_ERRORS)
async def store(node: NodeId, body: Confirm, services: ServicesDep) -> MessageResult:
    return await services.params.store(node, confirm=body.confirm)


@router.post("/restore-defaults", responses=CONFIRM_ERRORS)
async def restore_defaults(node: NodeId, body: Confirm, services: ServicesDep) -> MessageResult:
    return await services.params.restore_defaults(node, confirm=body.confirm)


@router.post("/change-node-id", responses=CONFIRM_ERRORS)
async def change_node_id(
    node: NodeId, body: NodeIdChange, services: ServicesDep
) -> NodeIdChangeResult:
    return await services.node_ids.change_node_id(node, body.new_node, confirm=body.confirm)


@router.get("/node-id-options")
async def node_id_options(node: NodeId, services: ServicesDep) -> NodeIdOptions:
    """Whether the node-id wizard can change this node's id, before its first step."""
    return services.node_ids.node_id_options(node)


@router.get("/bitrates")
async def bitrates(node: NodeId, services: ServicesDep) -> BitrateOptions:
    return await services.node_ids.bitrate_options(node)


@router.post("/change-bitrate", responses=CONFIRM_ERRORS)
async def change_bitrate(
    node: NodeId, body: BitrateChange, services: ServicesDep
) -> BitrateChangeResult:
    return await services.node_ids.change_bitrate(node, body.bitrate, confirm=body.confirm)
