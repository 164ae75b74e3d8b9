"""Commissioning records (docs/api.md, "Commissioning"): make one per axis, read them, run a
step's automated part, sign a step off. Paths and fields are a contract for outside scripts."""

from __future__ import annotations

from typing import Annotated

from fastapi import APIRouter, Path, Query

from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import NodeId, ServicesDep
from servodesk.api.errors import NODE_ERRORS
from servodesk.commissioning.models import (
    CommissioningCreate,
    CommissioningRecord,
    CommissioningStep,
    StepSignOff,
)
from servodesk.models import ErrorBody

router = APIRouter(tags=["commissioning"], route_class=AuditedRoute)

RecordId = Annotated[int, Path(ge=1, description="the record's id")]
StepKey = Annotated[str, Path(max_length=40, description="identity, communication, … store_verify")]
NOT_FOUND: dict[int | str, dict[str, object]] = {
    404: {
        "model": ErrorBody,
        "description": "commissioning_not_found (no such record) or step_not_found (no such "
        "step key)",
    }
}
RUN_ERRORS: dict[int | str, dict[str, object]] = {
    **NODE_ERRORS,
    **NOT_FOUND,
    409: {
        "model": ErrorBody,
        "description": "step_not_automated: do the step on its page and sign it off with PUT; "
        "or an SDO abort / node_stopped while running it",
    },
    504: {
        "model": ErrorBody,
        "description": "timeout: the node did not answer, or (store_verify) did not boot after "
        "the reset; the message names its NMT state and the step is recorded failed",
    },
}


@router.post("/nodes/{node}/commissioning", status_code=201, responses=NODE_ERRORS)
async def create_commissioning(
    node: NodeId, body: CommissioningCreate, services: ServicesDep
) -> CommissioningRecord:
    return await services.commissioning.create(node, body)


@router.get("/commissioning")
async def list_commissioning(
    services: ServicesDep, node: Annotated[int | None, Query(ge=1, le=127)] = None
) -> list[CommissioningRecord]:
    return await services.commissioning.list(node)


@router.get("/commissioning/{record_id}", responses=NOT_FOUND)
async def get_commissioning(record_id: RecordId, services: ServicesDep) -> CommissioningRecord:
    return await services.commissioning.get(record_id)


@router.put("/commissioning/{record_id}/steps/{key}", responses=NOT_FOUND)
async def sign_off_step(
    record_id: RecordId, key: StepKey, body: StepSignOff, services: ServicesDep
) -> CommissioningStep:
    return await services.commissioning.sign_off(record_id, key, body)


@router.post("/commissioning/{record_id}/steps/{key}/run", responses=RUN_ERRORS)
async def run_step(record_id: RecordId, key: StepKey, services: ServicesDep) -> CommissioningStep:
    return await services.commissioning.run(record_id, key)
