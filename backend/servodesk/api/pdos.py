"""PDO mapping: read, validate, apply (one transaction), recommend, export, live check; bus
load of the whole bus."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Query
from fastapi.responses import PlainTextResponse

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import NodeId, ServicesDep
from servodesk.api.errors import BUS_ERRORS, NODE_ERRORS, PDO_APPLY_ERRORS
from servodesk.models.pdo import (
    BusLoadResult,
    LiveCheck,
    Pdo,
    PdoIn,
    PdoList,
    PdoRules,
    PdoValidation,
    PdoWriteRequest,
)
from servodesk.pdo.bus_load import DEFAULT_MASTER_PERIOD_MS
from servodesk.pdo.model import MappedObject, PdoConfig
from servodesk.pdo.service import DEFAULT_THRESHOLD
from servodesk_protocol.pdo import transmission_words

router = APIRouter(
    prefix="/nodes/{node}/pdos", tags=["pdo"], responses=NODE_ERRORS, route_class=AuditedRoute
)
bus_router = APIRouter(tags=["pdo"], responses=BUS_ERRORS, route_class=AuditedRoute)

Modes = Annotated[
    str,
    Query(
        pattern=r"^[A-Za-z]+(,[A-Za-z]+)*$",
        description="operating modes, comma-separated: pp, pv, pt, hm, ip",
    ),
]
Threshold = Annotated[
    float, Query(ge=0, le=100, description="percent of the bitrate above which load is too high")
]
MasterPeriod = Annotated[
    int,
    Query(
        ge=1,
        le=60_000,
        description=(
            "ms: the master cycle assumed for event-driven RPDOs while no SYNC producer runs"
        ),
    ),
]
ExportFormat = Annotated[
    Literal["dcf", "python"],
    Query(alias="format", description="dcf: a DCF fragment; python: a python-canopen snippet"),
]


def to_api(pdo: PdoConfig) -> Pdo:
    words = transmission_words(pdo.transmission_type, pdo.direction)
    return Pdo.model_validate(pdo, from_attributes=True).model_copy(update={"transmission": words})


def from_api(pdo: PdoIn) -> PdoConfig:
    fields = pdo.model_dump(exclude={"mapping", "transmission"})
    mapping = tuple(MappedObject(o.index, o.subindex, o.bits) for o in pdo.mapping)
    return PdoConfig(**fields, mapping=mapping)


@router.get("")
async def read_pdos(node: NodeId, services: ServicesDep) -> list[Pdo]:
    return [to_api(pdo) for pdo in await services.pdos.read(node)]


@router.put("", responses=PDO_APPLY_ERRORS)
async def apply_pdos(node: NodeId, body: PdoWriteRequest, services: ServicesDep) -> list[Pdo]:
    pdos = [from_api(pdo) for pdo in body.pdos]
    applied = await services.pdos.apply(node, pdos, sync_source=body.sync_source)
    return [to_api(pdo) for pdo in applied]


@router.get("/rules")
async def pdo_rules(node: NodeId, services: ServicesDep) -> PdoRules:
    return services.pdos.rules(node)


@router.post("/validate")
async def validate_pdos(
    node: NodeId,
    body: PdoWriteRequest,
    services: ServicesDep,
    threshold: Threshold = DEFAULT_THRESHOLD,
    master_period_ms: MasterPeriod = DEFAULT_MASTER_PERIOD_MS,
) -> PdoValidation:
    pdos = [from_api(pdo) for pdo in body.pdos]
    return await services.pdos.validate(
        node,
        pdos,
        threshold=threshold,
        master_period_ms=master_period_ms,
        sync_source=body.sync_source,
    )


@router.get("/recommended")
async def recommended_pdos(node: NodeId, modes: Modes, services: ServicesDep) -> PdoList:
    names = [mode.strip().lower() for mode in modes.split(",")]
    return PdoList(pdos=[to_api(pdo) for pdo in await services.pdos.recommended(node, names)])


@router.get("/export", response_class=PlainTextResponse)
async def export_pdos(
    node: NodeId, services: ServicesDep, fmt: ExportFormat = "dcf"
) -> PlainTextResponse:
    text = await services.pdos.export(node, fmt)
    suffix = "dcf" if fmt == "dcf" else "py"
    filename = f"node{node}-pdos.{suffix}"
    return PlainTextResponse(
        text, headers={"Content-Disposition": f'attachment; filename="{filename}"'}
    )


@router.post("/live")
async def start_live(node: NodeId, services: ServicesDep) -> LiveCheck:
    return await services.pdos.start_live(node)


@router.get("/live")
async def live(node: NodeId, services: ServicesDep) -> LiveCheck:
    return services.pdos.live(node)


@router.delete("/live")
async def stop_live(node: NodeId, services: ServicesDep) -> LiveCheck:
    return services.pdos.stop_live(node)


@bus_router.get("/bus-load")
async def bus_load(
    services: ServicesDep,
    threshold: Threshold = DEFAULT_THRESHOLD,
    master_period_ms: MasterPeriod = DEFAULT_MASTER_PERIOD_MS,
) -> BusLoadResult:
    return await services.pdos.bus_load(threshold, master_period_ms=master_period_ms)
