"""A web page on another site must not change anything through the user's browser: every
state-changing route refuses foreign origins, for every body type a browser sends without
asking first (form, multipart, text/plain) and for JSON. The routes are taken from the app's
own schema, so a route added later is covered without editing this file."""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import Any

import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.settings import Settings

HOST = "127.0.0.1:8000"
EVIL = "http://evil.example"
PATH_VALUES = {
    "node": "3",
    "index": "6081",
    "subindex": "0",
    "name": "PA-14",
    "job_id": "x",
    "jog_id": "x",
    "capture_id": "1",
    "entry_id": "1",
    "log_id": "0" * 32,
    "record_id": "1",
    "key": "identity",
}
BODIES: dict[str, dict[str, Any]] = {
    "json": {"json": {"command": "start", "value": 1, "confirm": True}},
    "multipart": {"files": {"file": ("set.dcf", b"[6081sub0]\nParameterValue=777\n")}},
    "form": {"data": {"command": "start", "confirm": "true"}},
    "text": {"content": b'{"command": "start"}'},
}
DCF = b"""[DeviceInfo]
ProductName=evil
[DeviceComissioning]
NodeID=3
[6081]
ParameterName=Profile velocity
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=0
ParameterValue=4242
"""


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path_factory.mktemp("data"))
    app = create_app(settings, static_dir=None)
    with TestClient(app, base_url=f"http://{HOST}") as test_client:
        yield test_client


def state_changing_routes(client: TestClient) -> list[tuple[str, str]]:
    schema = client.get("/api/openapi.json").json()
    routes = []
    for template, item in schema["paths"].items():
        for method in item:
            if method in ("post", "put", "patch", "delete"):
                path = re.sub(r"\{(\w+)\}", lambda m: PATH_VALUES[m.group(1)], template)
                routes.append((method.upper(), path))
    return routes


def assert_refused(response: Any, source: str) -> None:
    assert response.status_code == 403, response.text
    assert response.json() == {
        "error": "cross_origin",
        "message": f"refused a request from {source}: ServoDesk accepts changes only from its "
        "own pages",
    }


def test_the_schema_lists_the_write_routes(client: TestClient) -> None:
    routes = state_changing_routes(client)
    assert ("POST", "/api/nodes/3/dcf") in routes
    assert ("POST", "/api/nodes/3/nmt") in routes
    assert ("PUT", "/api/nodes/3/sdo/6081/0") in routes
    assert len(routes) >= 15


@pytest.mark.parametrize("body", sorted(BODIES))
@pytest.mark.parametrize("origin", [EVIL, "null", "http://localhost:5173"])
def test_every_write_route_refuses_a_foreign_origin(
    client: TestClient, body: str, origin: str
) -> None:
    for method, path in state_changing_routes(client):
        headers = {"origin": origin}
        if body == "text":
            headers["content-type"] = "text/plain"
        response = client.request(method, path, headers=headers, **BODIES[body])
        assert_refused(response, origin)


def value_6081(client: TestClient) -> Any:
    return client.get("/api/nodes/3/sdo/6081/0").json()["value"]


def test_a_cross_site_parameter_set_changes_nothing_on_the_drive(client: TestClient) -> None:
    before = value_6081(client)
    for kind, headers in [
        ("origin", {"origin": EVIL}),
        ("fetch metadata", {"sec-fetch-site": "cross-site"}),
        ("referer", {"referer": f"{EVIL}/attack.html"}),
    ]:
        response = client.post(
            "/api/nodes/3/dcf", files={"file": ("set.dcf", DCF)}, headers=headers
        )
        assert response.status_code == 403, kind
    assert value_6081(client) == before != 4242


def test_a_cross_site_nmt_start_changes_nothing(client: TestClient) -> None:
    state = client.get("/api/nodes/2").json()["nmt_state"]
    response = client.post("/api/nodes/2/nmt", json={"command": "stop"}, headers={"origin": EVIL})
    assert_refused(response, EVIL)
    assert client.get("/api/nodes/2").json()["nmt_state"] == state


def test_own_pages_and_scripts_still_write(client: TestClient) -> None:
    own = {"origin": f"http://{HOST}", "sec-fetch-site": "same-origin"}
    written = client.put("/api/nodes/3/sdo/6081/0", json={"value": 1234}, headers=own)
    assert written.status_code == 200, written.text
    alias = {"origin": "http://localhost:8000"}
    assert client.put("/api/nodes/3/sdo/6081/0", json={"value": 1235}, headers=alias).is_success
    # curl and scripts send none of Origin, Sec-Fetch-Site, Referer
    assert client.put("/api/nodes/3/sdo/6081/0", json={"value": 1236}).is_success
    assert value_6081(client) == 1236
    same_site_referer = {"referer": f"http://{HOST}/nodes/3/params"}
    assert client.put(
        "/api/nodes/3/sdo/6081/0", json={"value": 1237}, headers=same_site_referer
    ).is_success


def test_reads_are_not_blocked(client: TestClient) -> None:
    # a foreign page cannot read the answer anyway (no CORS headers); GETs change nothing
    assert client.get("/api/health", headers={"origin": EVIL}).status_code == 200


def test_the_websocket_refuses_a_foreign_origin(client: TestClient) -> None:
    from starlette.websockets import WebSocketDisconnect

    with (
        pytest.raises(WebSocketDisconnect),
        client.websocket_connect("/api/ws", headers={"origin": EVIL}) as socket,
    ):
        socket.receive_json()
