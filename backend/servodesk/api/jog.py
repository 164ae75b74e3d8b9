"""Hold-to-run jogs (docs/api.md, Jog): start, keep alive, stop. A jog stops by itself when its
keep-alives stop (motion/jog.py)."""

from __future__ import annotations

from fastapi import APIRouter

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import NodeId, ServicesDep
from servodesk.api.drive import ClientDep
from servodesk.api.errors import JOG_ERRORS, MOTION_ERRORS
from servodesk.models.safety import JogInfo, JogRequest
from servodesk.motion.stop_reasons import Reason

router = APIRouter(tags=["jog"], route_class=AuditedRoute)


@router.post("/nodes/{node}/jog", responses=MOTION_ERRORS)
async def start_jog(
    node: NodeId, request: JogRequest, client: ClientDep, services: ServicesDep
) -> JogInfo:
    """Start moving (pv: velocity_rpm, pt: torque_pct, capped at speed_cap_rpm); send a
    keep-alive (REST or WebSocket `jog_keepalive`) at least every keepalive_ms or the axis
    stops. A script without X-Client-Id gets an owner id of its own (`owner`) and the drive's
    heartbeat protection until its jog's axis is at rest."""
    return await services.safety.start_jog(node, request, client)


@router.get("/jog/{jog_id}", responses=JOG_ERRORS)
async def get_jog(jog_id: str, services: ServicesDep) -> JogInfo:
    return services.safety.jogs.get(jog_id)


@router.post("/jog/{jog_id}/keepalive", responses=JOG_ERRORS)
async def keepalive(jog_id: str, client: ClientDep, services: ServicesDep) -> JogInfo:
    """Keep the jog moving; 409 jog_stopped once it was stopped (re-arming is explicit); 403
    not_jog_owner from anyone but the login (and the X-Client-Id, where sent) that started it."""
    return services.safety.keepalive(jog_id, client)


@router.delete("/jog/{jog_id}", responses=JOG_ERRORS)
async def stop_jog(jog_id: str, services: ServicesDep) -> JogInfo:
    """Stop the jog (anyone may); answers once the stop was sent to the drive, with state
    "stopping" until the axis is at rest."""
    return await services.safety.jogs.stop(jog_id, Reason("stop.user"))
