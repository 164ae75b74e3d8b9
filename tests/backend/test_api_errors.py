"""The one error mapping: every domain error becomes the status and body docs/api.md promises."""

from __future__ import annotations

import json

import pytest

from servodesk.api.errors import error_response
from servodesk.api.security import origin_allowed
from servodesk.errors import (
    BusNotConnectedError,
    CommTimeoutError,
    ConfirmationRequiredError,
    InvalidValueError,
    NodeNotFoundError,
    SdoAbortError,
    SdoProtocolError,
    ServodeskError,
)


@pytest.mark.parametrize(
    ("error", "status", "body"),
    [
        (
            SdoAbortError(0x06010002, 1, 0x6041, 0),
            409,
            {
                "error": "sdo_abort",
                "message": "Attempt to write a read-only object",
                "abort_code": "0x06010002",
                "node": 1,
                "index": 0x6041,
                "subindex": 0,
            },
        ),
        (
            SdoAbortError(0x12345678, 3, 0x2000, 1),
            409,
            {
                "error": "sdo_abort",
                "message": "Unknown abort code (vendor-specific or not in CiA 301)",
                "abort_code": "0x12345678",
                "node": 3,
                "index": 0x2000,
                "subindex": 1,
            },
        ),
        (
            CommTimeoutError(5, "read 1008h:00h"),
            504,
            {
                "error": "timeout",
                "message": "node 5: no answer to read 1008h:00h",
                "node": 5,
                "message_id": "error.no_answer_read",
                "params": {"node": 5, "where": "1008h:00h"},
            },
        ),
        (
            SdoProtocolError(5, "read 1008h:00h", "Toggle bit mismatch"),
            502,
            {
                "error": "sdo_protocol",
                "message": "node 5: read 1008h:00h failed: Toggle bit mismatch; "
                "the transfer was aborted",
                "node": 5,
            },
        ),
        (
            NodeNotFoundError(9),
            404,
            {
                "error": "node_not_found",
                "message": "node 9 is not known; scan the bus first",
                "node": 9,
                "message_id": "error.node_not_found",
                "params": {"node": 9},
            },
        ),
        (
            BusNotConnectedError(),
            503,
            {
                "error": "bus_not_connected",
                "message": "the CAN bus is not connected",
                "message_id": "error.bus_not_connected",
                "params": {},
            },
        ),
        (
            InvalidValueError("PA-106 must be 0–6"),
            422,
            {"error": "invalid_value", "message": "PA-106 must be 0–6"},
        ),
        (
            ConfirmationRequiredError("confirm storing"),
            428,
            {"error": "confirmation_required", "message": "confirm storing"},
        ),
        (ServodeskError("odd"), 500, {"error": "error", "message": "odd"}),
    ],
)
def test_error_mapping(error: ServodeskError, status: int, body: dict[str, object]) -> None:
    response = error_response(error)
    assert response.status_code == status
    assert json.loads(bytes(response.body)) == body


@pytest.mark.parametrize(
    ("origin", "allowed"),
    [
        (None, True),  # scripts, curl: no Origin header
        ("http://127.0.0.1:8000", True),
        ("http://localhost:8000", True),  # another name of the same loopback server
        ("http://localhost:5173", False),  # another local web app on another port
        ("file://", False),
        ("http://[::1]:8000", True),
        ("http://evil.example", False),
        ("http://127.0.0.1.evil.example", False),
        ("null", False),
    ],
)
def test_websocket_origin(origin: str | None, allowed: bool) -> None:
    assert origin_allowed(origin, "127.0.0.1:8000") is allowed
