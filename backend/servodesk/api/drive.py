"""The CiA 402 drive panel's routes (docs/api.md, Drive): state, enable (and why not), moves,
homing, interpolated streams, limits, and who controls the drive.

Every command that moves or powers the drive passes the controller lease first (motion/lease.py):
a client names itself with `X-Client-Id`; another client's command answers 409 held_by_other.
Quick stop is open to everyone.
"""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Depends, Header

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import NodeId, ServicesDep
from servodesk.api.errors import MOTION_ERRORS, NODE_ERRORS
from servodesk.models.motion import (
    DriveCommandRequest,
    DriveState,
    HomeRequest,
    HomingMethodInfo,
    IpStreamRequest,
    IpStreamResult,
    MotionLimits,
    MoveQueueRequest,
    MoveRequest,
)
from servodesk.models.safety import (
    ControllerInfo,
    LimitsRequest,
    QuickStopResult,
    TakeControlRequest,
)
from servodesk.motion.lease import Client
from servodesk.motion.stop_reasons import Reason

router = APIRouter(tags=["drive"], responses=MOTION_ERRORS, route_class=AuditedRoute)

CLIENT_ID = r"^[A-Za-z0-9._:-]{1,64}$"


async def get_client(
    x_client_id: Annotated[
        str | None,
        Header(pattern=CLIENT_ID, description="who sends this: the page's (or script's) id"),
    ] = None,
    x_client_name: Annotated[
        str | None, Header(max_length=64, description="shown to others as the holder")
    ] = None,
) -> Client:
    if x_client_id is None:
        return Client.anonymous_one()
    return Client(id=x_client_id, name=x_client_name)


ClientDep = Annotated[Client, Depends(get_client)]


@router.get("/nodes/{node}/drive", responses=NODE_ERRORS)
async def drive_state(node: NodeId, services: ServicesDep) -> DriveState:
    """The drive now, as every page and client shares it: the values its TPDOs carry from the
    frames, the rest by SDO within a small budget per period (`sources` says which)."""
    return await services.motion.polled_state(node)


@router.post("/nodes/{node}/drive/enable")
async def enable(node: NodeId, client: ClientDep, services: ServicesDep) -> DriveState:
    """Walk the CiA 402 state machine to Operation enabled; 409 enable_blocked names why not.
    A fault is never reset here (409 naming it, nothing sent): fault-reset is its own act."""
    await services.safety.authorize(node, client)
    return await services.motion.enable(node)


@router.post("/nodes/{node}/drive/disable")
async def disable(node: NodeId, client: ClientDep, services: ServicesDep) -> DriveState:
    await services.safety.authorize(node, client)
    services.safety.jogs.stop_node(node, Reason("stop.drive_disabled"))
    return await services.motion.disable(node)


@router.post("/nodes/{node}/drive/command")
async def command(
    node: NodeId, request: DriveCommandRequest, client: ClientDep, services: ServicesDep
) -> DriveState:
    """One CiA 402 controlword command (shutdown 0006h, switch on 0007h, enable operation 000Fh,
    disable operation 0007h, disable voltage 0000h, quick stop 0002h, fault reset 0000h → 0080h
    → 0000h). Quick stop is open to everyone, the others pass the lease. A command that takes
    no transition from the drive's state, or whose transition does not happen, answers 409
    enable_blocked with the reasons."""
    return await services.safety.command(node, request.command, client)


@router.post("/nodes/{node}/drive/quick-stop")
async def quick_stop(node: NodeId, services: ServicesDep) -> DriveState:
    """Open to every client, whoever controls the drive."""
    return await services.safety.quick_stop(node)


@router.post("/nodes/{node}/drive/fault-reset")
async def fault_reset(node: NodeId, client: ClientDep, services: ServicesDep) -> DriveState:
    await services.safety.authorize(node, client)
    return await services.motion.fault_reset(node)


@router.post("/nodes/{node}/drive/move", status_code=202)
async def move(
    node: NodeId, request: MoveRequest, client: ClientDep, services: ServicesDep
) -> DriveState:
    """Accepted: the move runs on; its progress is the drive state's `move`."""
    await services.safety.authorize(node, client)
    return await services.motion.move(node, request)


@router.post("/nodes/{node}/drive/move-queue", status_code=202)
async def move_queue(
    node: NodeId, request: MoveQueueRequest, client: ClientDep, services: ServicesDep
) -> DriveState:
    await services.safety.authorize(node, client)
    return await services.motion.move_queue(node, request)


@router.post("/nodes/{node}/drive/home", status_code=202)
async def home(
    node: NodeId, request: HomeRequest, client: ClientDep, services: ServicesDep
) -> DriveState:
    """Accepted: homing runs on; its progress is the drive state's `homing`."""
    await services.safety.authorize(node, client)
    return await services.motion.home(node, request)


@router.get("/nodes/{node}/drive/homing-methods", responses=NODE_ERRORS)
async def homing_methods(node: NodeId, services: ServicesDep) -> list[HomingMethodInfo]:
    return services.motion.homing_methods(node)


@router.post("/nodes/{node}/drive/ip-stream")
async def ip_stream(
    node: NodeId, request: IpStreamRequest, client: ClientDep, services: ServicesDep
) -> IpStreamResult:
    """Runs the whole stream (up to 30 s) and answers how closely the axis followed."""
    await services.safety.authorize(node, client)
    return await services.motion.ip_stream(
        node,
        request.trajectory,
        period_ms=request.period_ms,
        distance_rev=request.distance_rev,
        duration_s=request.duration_s,
    )


@router.get("/nodes/{node}/drive/limits", responses=NODE_ERRORS)
async def limits(node: NodeId, services: ServicesDep) -> MotionLimits:
    services.registry.info(node)
    return services.motion.limits(node)


@router.put("/nodes/{node}/drive/limits")
async def set_limits(
    node: NodeId, request: LimitsRequest, client: ClientDep, services: ServicesDep
) -> MotionLimits:
    await services.safety.authorize(node, client)
    return services.motion.set_limits(node, MotionLimits(**request.model_dump()))


@router.get("/nodes/{node}/drive/controller", responses=NODE_ERRORS)
async def controller(node: NodeId, client: ClientDep, services: ServicesDep) -> ControllerInfo:
    """Who controls the drive, and whether it stops by itself if ServoDesk dies."""
    return services.safety.controller(node, client)


@router.post("/nodes/{node}/drive/controller")
async def take_control(
    node: NodeId, request: TakeControlRequest, client: ClientDep, services: ServicesDep
) -> ControllerInfo:
    """Take the drive (needs X-Client-Id); held by another client → 409 held_by_other unless
    `take_over` (the other client's jogs then stop)."""
    if request.name is not None:
        client = Client(id=client.id, name=request.name, anonymous=client.anonymous)
    return await services.safety.take(node, client, take_over=request.take_over)


@router.delete("/nodes/{node}/drive/controller")
async def release_control(node: NodeId, client: ClientDep, services: ServicesDep) -> ControllerInfo:
    """Release the drive: its jogs stop and its heartbeat consumer entry is restored."""
    return await services.safety.release(node, client)


@router.post("/quick-stop", responses=NODE_ERRORS)
async def quick_stop_all(services: ServicesDep) -> QuickStopResult:
    """Quick stop every known drive (the Network page's one click); open to every client."""
    return await services.safety.quick_stop_all()
