"""The API contract as a client meets it: every error in the one documented shape, the statuses
in the OpenAPI schema, strict path and body types, `Allow` naming the real methods."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.settings import Settings


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path_factory.mktemp("data"))
    app = create_app(settings, static_dir=None)
    with TestClient(app, raise_server_exceptions=False) as test_client:
        yield test_client


def error_of(response: Any, status: int) -> dict[str, Any]:
    assert response.status_code == status, response.text
    body: dict[str, Any] = response.json()
    assert isinstance(body.get("error"), str)
    assert isinstance(body.get("message"), str)
    assert "detail" not in body
    return body


@pytest.mark.parametrize(
    ("method", "path", "body", "says"),
    [
        ("put", "/api/nodes/1/heartbeat", {"producer_ms": "12"}, "producer_ms"),
        ("post", "/api/nodes/1/store", {"confirm": "true"}, "confirm"),
        ("post", "/api/nodes/1/store", {"comfirm": True}, "comfirm"),
        ("put", "/api/nodes/1/sdo/6060/0", {}, "value"),
        ("put", "/api/nodes/1/sdo/6060/0", {"value": 1, "size": 3}, "size"),
        ("post", "/api/nodes/1/nmt", {"command": "jump"}, "command"),
        ("post", "/api/scan", {"timeout_ms": 1.5}, "timeout_ms"),
        ("get", "/api/nodes/0", None, "node"),
        ("get", "/api/nodes/128/sdo/1008/0", None, "node"),
        ("get", "/api/nodes/1/sdo/60410/0", None, "index"),
        ("get", "/api/nodes/1/sdo/zz41/0", None, "index"),
        ("get", "/api/nodes/1/sdo/6041/100", None, "subindex"),
        ("get", "/api/jobs/x?since=-1", None, "since"),
    ],
)
def test_invalid_requests_are_refused_in_the_documented_shape(
    client: TestClient, method: str, path: str, body: Any, says: str
) -> None:
    kwargs = {} if body is None else {"json": body}
    refused = error_of(client.request(method, path, **kwargs), 422)
    assert refused["error"] == "invalid_request"
    assert says in refused["message"]


def test_an_unparsable_body_is_a_400_in_the_documented_shape(client: TestClient) -> None:
    response = client.put(
        "/api/nodes/1/sdo/6060/0",
        content=b'{"value": ',
        headers={"content-type": "application/json"},
    )
    assert response.status_code in (400, 422)
    error_of(response, response.status_code)


def test_unknown_routes_and_methods(client: TestClient) -> None:
    assert error_of(client.get("/api/nope"), 404)["error"] == "not_found"
    wrong = client.post("/api/nodes/1/sdo/6060/0")
    assert error_of(wrong, 405)["error"] == "method_not_allowed"
    assert wrong.headers["allow"] == "GET, HEAD, PUT"
    assert client.delete("/api/health").headers["allow"] == "GET, HEAD"


def test_the_working_bus_is_untouched_by_an_incomplete_configuration(client: TestClient) -> None:
    refused = error_of(client.post("/api/bus/connect", json={}), 422)
    assert "no CAN interface" in refused["message"]
    assert client.get("/api/bus").json()["state"] == "connected"
    assert [n["node"] for n in client.get("/api/nodes").json()] == [1, 2, 3]
    unknown = error_of(client.post("/api/bus/connect", json={"interface": "nonsense"}), 422)
    assert "nonsense" in unknown["message"]
    assert client.get("/api/bus").json()["state"] == "connected"


def test_every_error_status_in_the_schema_has_the_documented_shape(client: TestClient) -> None:
    schema = client.get("/api/openapi.json").json()
    components = schema["components"]["schemas"]
    assert "HTTPValidationError" not in components
    # MotionErrorBody is ErrorBody plus the motion routes' extras (holder, reasons, state)
    base = components["ErrorBody"]
    extended = components["MotionErrorBody"]
    assert set(base["properties"]) <= set(extended["properties"])
    assert extended["required"] == base["required"]
    shapes = {"#/components/schemas/ErrorBody", "#/components/schemas/MotionErrorBody"}
    for path, item in schema["paths"].items():
        for method, operation in item.items():
            for status, response in operation["responses"].items():
                if status.startswith("2"):
                    continue
                ref = response["content"]["application/json"]["schema"]["$ref"]
                assert ref in shapes, (method, path, status)
            if method in ("post", "put", "delete"):
                assert "403" in operation["responses"], (method, path)


@pytest.mark.parametrize(
    ("method", "path", "statuses"),
    [
        ("post", "/api/nodes/{node}/store", {"409", "422", "428", "503", "504"}),
        ("post", "/api/nodes/{node}/restore-defaults", {"428"}),
        ("post", "/api/nodes/{node}/dcf", {"400", "422", "428"}),
        (
            "put",
            "/api/nodes/{node}/sdo/{index}/{subindex}",
            {"400", "404", "409", "502", "503", "504"},
        ),
        ("post", "/api/bus/connect", {"400", "422"}),
    ],
)
def test_the_schema_declares_what_a_route_can_answer(
    client: TestClient, method: str, path: str, statuses: set[str]
) -> None:
    operation = client.get("/api/openapi.json").json()["paths"][path][method]
    assert statuses <= set(operation["responses"])


def test_an_unexpected_failure_is_one_line_in_the_documented_shape(
    client: TestClient, tmp_path: Path
) -> None:
    services = client.app.state.services  # type: ignore[attr-defined]
    original = services.registry.all

    def broken() -> Any:
        raise ZeroDivisionError("division by zero")

    services.registry.all = broken
    try:
        failed = error_of(client.get("/api/nodes"), 500)
    finally:
        services.registry.all = original
    assert failed == {
        "error": "internal",
        "message": "internal error (ZeroDivisionError); see the log",
    }
