"""The one place where domain errors become HTTP answers (docs/api.md, "Errors")."""

from __future__ import annotations

from fastapi import FastAPI, Request
from fastapi.responses import JSONResponse

from servodesk.errors import (
    BusNotConnectedError,
    CommTimeoutError,
    ConfirmationRequiredError,
    InvalidValueError,
    NodeNotFoundError,
    SdoAbortError,
    ServodeskError,
)
from servodesk.models import ErrorBody
from servodesk.sdo.jobs import JobNotFoundError


def error_response(error: ServodeskError) -> JSONResponse:
    status, body = _describe(error)
    return JSONResponse(status_code=status, content=body.model_dump(exclude_none=True))


def _describe(error: ServodeskError) -> tuple[int, ErrorBody]:
    if isinstance(error, SdoAbortError):
        return 409, ErrorBody(
            error="sdo_abort",
            message=error.meaning,
            abort_code=error.code_hex,
            node=error.node_id,
            index=error.index,
            subindex=error.subindex,
        )
    if isinstance(error, CommTimeoutError):
        return 504, ErrorBody(error="timeout", message=str(error), node=error.node_id)
    if isinstance(error, JobNotFoundError):
        return 404, ErrorBody(error="job_not_found", message=str(error))
    if isinstance(error, NodeNotFoundError):
        return 404, ErrorBody(error="node_not_found", message=str(error), node=error.node_id)
    if isinstance(error, BusNotConnectedError):
        return 503, ErrorBody(error="bus_not_connected", message=str(error))
    if isinstance(error, InvalidValueError):
        return 422, ErrorBody(error="invalid_value", message=str(error))
    if isinstance(error, ConfirmationRequiredError):
        return 428, ErrorBody(error="confirmation_required", message=str(error))
    return 500, ErrorBody(error="error", message=str(error))


def install_error_handlers(app: FastAPI) -> None:
    async def handle(_request: Request, error: Exception) -> JSONResponse:
        if not isinstance(error, ServodeskError):  # registered for ServodeskError only
            raise error
        return error_response(error)

    app.add_exception_handler(ServodeskError, handle)


# Responses every node route can give, for the OpenAPI schema (and so the generated client).
NODE_ERRORS: dict[int | str, dict[str, object]] = {
    404: {"model": ErrorBody, "description": "Unknown node"},
    409: {"model": ErrorBody, "description": "SDO abort (abort_code and its meaning)"},
    422: {"model": ErrorBody, "description": "Invalid value"},
    503: {"model": ErrorBody, "description": "Bus not connected"},
    504: {"model": ErrorBody, "description": "Node did not answer"},
}
