"""Commissioning records (docs/api.md, "Commissioning"): make one per axis, read them, run a
step's automated part, sign a step off. Paths and fields are a contract for outside scripts."""

from __future__ import annotations

import asyncio
from typing import Annotated

from fastapi import APIRouter, Form, Path, Query, Request, Response
from fastapi.exceptions import RequestValidationError
from pydantic import ValidationError

from servodesk.api import report_files
from servodesk.api.audited import AuditedRoute
from servodesk.api.deps import NodeId, ServicesDep
from servodesk.api.errors import NODE_ERRORS
from servodesk.api.uploads import Upload
from servodesk.commissioning.check import FieldCheck, HandOver, open_bundle
from servodesk.commissioning.check_core import CheckResult
from servodesk.commissioning.report import MachineFormat, ReportFormat
from servodesk.commissioning.report_words import Lang
from servodesk.errors import InvalidValueError
from servodesk.models.commissioning import (
    CheckRequest,
    CommissioningCreate,
    CommissioningRecord,
    CommissioningStep,
    StepRun,
    StepSignOff,
)
from servodesk.models.common import ErrorBody

router = APIRouter(tags=["commissioning"], route_class=AuditedRoute)

RecordId = Annotated[int, Path(ge=1, le=2**53, description="the record's id")]
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


IdList = Annotated[str | None, Query(pattern=r"^\d{1,9}(,\d{1,9}){0,127}$", description="1,2,3")]
ReportLang = Annotated[
    Lang, Query(description="the report's own words: en (default) or zh-CN; data stays as stored")
]
REPORT_RESPONSES: dict[int | str, dict[str, object]] = {
    **NOT_FOUND,
    200: {
        "content": {"text/html": {}, "application/pdf": {}, "application/zip": {}},
        "description": "the report as an HTML page or a PDF; zip: the record's bundle",
    },
}


# before /commissioning/{record_id}: "report" is not a record id
@router.get("/commissioning/report", response_class=Response, responses=REPORT_RESPONSES)
async def machine_report(
    services: ServicesDep,
    format: MachineFormat = "html",  # the query parameter's name
    ids: IdList = None,
    nodes: IdList = None,
    lang: ReportLang = "en",
) -> Response:
    """One report for a machine: the listed records (`ids`), else the latest record of each
    listed node (`nodes`), else the latest record of every node, by node."""
    records = await report_files.machine_records(
        services, report_files.numbers(ids), report_files.numbers(nodes)
    )
    name = "servodesk-commissioning-machine"
    return await report_files.answer(services, records, format, name, lang)


CHECK_ERRORS: dict[int | str, dict[str, object]] = {
    **NODE_ERRORS,
    **NOT_FOUND,
    422: {
        "model": ErrorBody,
        "description": "invalid_value: the upload is not a ServoDesk bundle (no record.json), "
        "or no bundle/record_id was given; invalid_request: an unknown field",
    },
}
# The route reads either body itself: the JSON form is said in the schema by hand
CHECK_BODY: dict[str, object] = {
    "requestBody": {
        "required": True,
        "content": {"application/json": {"schema": CheckRequest.model_json_schema()}},
    }
}


@router.post("/commissioning/check", responses=CHECK_ERRORS, openapi_extra=CHECK_BODY)
async def check_record(
    request: Request,
    services: ServicesDep,
    bundle: Upload = None,
    node: Annotated[
        str | None,
        Form(max_length=8, description="node 1–127; default: the record's"),
    ] = None,
) -> CheckResult:
    """The drive now against its hand-over: JSON `{"record_id", "node"?}` (a record of this
    server), or a multipart upload of a bundle zip (`bundle`) and `node`. Only reads."""
    if bundle is None or isinstance(bundle, str):
        if request.headers.get("content-type", "").startswith("multipart/"):
            raise InvalidValueError(
                "no bundle given: send the zip as the multipart file field 'bundle'"
            )
        raw = await request.body()
        if not raw.strip():
            raise InvalidValueError(
                'nothing to check against: send {"record_id": …} as JSON, or a bundle zip '
                "as the multipart file field 'bundle'"
            )
        try:
            body = CheckRequest.model_validate_json(raw)
        except ValidationError as error:
            raise RequestValidationError(error.errors(include_url=False)) from None
        hand_over = HandOver(await services.commissioning.get(body.record_id), "record")
        node_id = body.node
    else:
        node_id = _form_node(node)
        hand_over = await asyncio.to_thread(open_bundle, bundle.file)
    check = FieldCheck(services.registry, services.od_parser, services.faults,
                       audit=services.audit)  # fmt: skip
    return await check.run(hand_over, node_id)


def _form_node(text: str | None) -> int | None:
    """A form field is text: empty (or a client's "null") is the record's node."""
    value = (text or "").strip()
    if value in ("", "null"):
        return None
    if not value.isdigit() or not 1 <= int(value) <= 127:
        raise InvalidValueError(f"node {value!r}: give a node id from 1 to 127")
    return int(value)


# `:int`: /commissioning/check (POST) and /commissioning/report are not record ids; a GET of
# /commissioning/check is then 405 (the path has a POST), not a 422 about a record id
@router.get("/commissioning/{record_id:int}", responses=NOT_FOUND)
async def get_commissioning(record_id: RecordId, services: ServicesDep) -> CommissioningRecord:
    return await services.commissioning.get(record_id)


@router.put("/commissioning/{record_id}/steps/{key}", responses=NOT_FOUND)
async def sign_off_step(
    record_id: RecordId, key: StepKey, body: StepSignOff, services: ServicesDep
) -> CommissioningStep:
    return await services.commissioning.sign_off(record_id, key, body)


@router.post("/commissioning/{record_id}/steps/{key}/run", responses=RUN_ERRORS)
async def run_step(
    record_id: RecordId, key: StepKey, services: ServicesDep, body: StepRun | None = None
) -> CommissioningStep:
    """Optional body: stop_test `{"speed_rpm"}`, test_move `{"distance"}` (rev); no body or
    `{}` runs a step with its defaults."""
    return await services.commissioning.run(record_id, key, body)


@router.get(
    "/commissioning/{record_id}/report", response_class=Response, responses=REPORT_RESPONSES
)
async def record_report(
    record_id: RecordId,
    services: ServicesDep,
    format: ReportFormat = "html",  # the query parameter's name
    lang: ReportLang = "en",
) -> Response:
    """The axis's hand-over report as HTML or PDF, or its bundle (zip), in English or
    Chinese (`lang`)."""
    record = await services.commissioning.get(record_id)
    name = f"servodesk-commissioning-{record.id}-node{record.node}"
    return await report_files.answer(services, [record], format, name, lang)
