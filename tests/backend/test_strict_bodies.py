"""Request bodies are strict: an unknown field is refused (422, naming it) on every route,
those that take no body included; true/false is not a number for a drive write; a heartbeat
time below 10 ms through a raw SDO write needs confirm, as on the heartbeat route."""

from __future__ import annotations

import time
from collections.abc import Iterator
from typing import Any, get_args

import pytest
from fastapi.routing import APIRoute
from fastapi.testclient import TestClient
from pydantic import BaseModel

from servodesk.api.no_body import problems
from servodesk.app import create_app
from servodesk.settings import Settings

LINK = '=HYPERLINK("http://evil.example","x")'


def models_in(annotation: Any) -> Iterator[type[BaseModel]]:
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        yield annotation
        for field in annotation.model_fields.values():
            yield from models_in(field.annotation)
    for arg in get_args(annotation):
        yield from models_in(arg)


def test_every_request_model_refuses_unknown_fields() -> None:
    app = create_app(Settings(simulated=True), static_dir=None)
    checked: set[str] = set()
    for route in app.routes:
        if not isinstance(route, APIRoute) or route.body_field is None:
            continue
        for param in route.dependant.body_params:
            for model in models_in(param.field_info.annotation):
                assert model.model_config.get("extra") == "forbid", (route.path, model)
                checked.add(model.__name__)
    assert {"SdoWrite", "UndoRequest", "PdoWriteRequest", "JogRequest"} <= checked


@pytest.mark.parametrize(
    ("body", "refused"),
    [
        (b"", False),
        (b"  ", False),
        (b"{}", False),
        (b"null", False),
        (b'{"value": 1}', True),
        (b"[1]", True),
        (b"quick stop please", True),
    ],
)
def test_a_route_without_a_body_takes_none(body: bytes, refused: bool) -> None:
    assert bool(problems(body)) == refused


@pytest.mark.parametrize(
    ("method", "path"),
    [
        ("POST", "/api/nodes/3/drive/enable"),
        ("POST", "/api/nodes/3/drive/fault-reset"),
        ("DELETE", "/api/nodes/3/drive/controller"),
    ],
)
def test_a_body_with_fields_a_route_does_not_know_is_refused(
    client: TestClient, method: str, path: str
) -> None:
    answer = client.request(method, path, json={"value": LINK})
    assert answer.status_code == 422, answer.text
    assert answer.json()["error"] == "invalid_request"
    assert answer.json()["message"].startswith("value: unknown field")


def test_quick_stop_with_no_body_or_an_empty_one_stops(client: TestClient) -> None:
    assert client.post("/api/quick-stop").status_code == 200
    assert client.post("/api/quick-stop", json={}).status_code == 200


@pytest.mark.parametrize(
    ("method", "path", "status"),
    [
        ("POST", "/api/quick-stop", 200),
        ("POST", "/api/nodes/3/drive/quick-stop", 200),
        ("POST", "/api/nodes/3/drive/disable", 200),
        ("DELETE", "/api/jog/j-1", 404),  # no such jog: said so, not a body error
    ],
)
def test_a_stop_with_a_stray_body_still_stops_and_keeps_none_of_it(
    client: TestClient, method: str, path: str, status: int
) -> None:
    """Stopping is never refused: the body is ignored (and said to be), nothing of it is
    kept in the audit log."""
    if status == 200:
        enabled = client.post("/api/nodes/3/drive/enable", headers={"X-Client-Id": "t"})
        assert enabled.json()["state"] == "operation_enabled"
    answer = client.request(method, path, json={"value": LINK}, headers={"X-Client-Id": "t"})
    assert answer.status_code == status, answer.text
    if status == 200:
        assert answer.headers["X-Body-Ignored"] == "this request takes no body: value"
        state = client.get("/api/nodes/3/drive").json()["state"]
        assert state in {"quick_stop_active", "switch_on_disabled", "ready_to_switch_on"}
    entry = client.get("/api/audit", params={"limit": 1}).json()[0]
    assert "HYPERLINK" not in str(entry)
    assert entry["result"] == ("ok" if status == 200 else "failed")


def test_an_unknown_field_on_a_write_is_named(client: TestClient) -> None:
    before = client.get("/api/nodes/1/sdo/6081/0").json()["value"]
    answer = client.put("/api/nodes/1/sdo/6081/0", json={"value": 1234, "comment": LINK})
    assert answer.status_code == 422
    assert answer.json()["error"] == "invalid_request"
    assert answer.json()["message"] == "comment: Extra inputs are not permitted"
    assert client.get("/api/nodes/1/sdo/6081/0").json()["value"] == before


@pytest.mark.parametrize(
    "path", ["/api/nodes/1/sdo/6081/0", "/api/nodes/1/sdo/1017/0", "/api/nodes/1/params/PA-14"]
)
def test_true_is_not_a_number_for_a_drive_write(client: TestClient, path: str) -> None:
    before = client.get(path).json()["value"]
    answer = client.put(path, json={"value": True})
    assert answer.status_code == 422, answer.text
    assert "true/false" in answer.json()["message"]
    assert client.get(path).json()["value"] == before


def test_a_fast_heartbeat_by_raw_sdo_write_needs_confirm(client: TestClient) -> None:
    heartbeat = "/api/nodes/2/sdo/1017/0"
    before = client.get(heartbeat).json()["value"]
    refused = client.put(heartbeat, json={"value": 1})
    assert refused.status_code == 428
    assert refused.json()["error"] == "confirmation_required"
    assert "below 10 ms needs confirm" in refused.json()["message"]
    assert client.get(heartbeat).json()["value"] == before
    assert client.put(heartbeat, json={"value": "0x0001"}).status_code == 428
    confirmed = client.put(heartbeat, json={"value": 1, "confirm": True})
    assert confirmed.status_code == 200
    assert confirmed.json()["value"] == 1
    assert client.put(heartbeat, json={"value": 100}).status_code == 200
    assert client.put(heartbeat, json={"value": 0}).status_code == 200  # off is not fast


def test_a_live_channel_stop_with_a_stray_field_still_stops(client: TestClient) -> None:
    enabled = client.post("/api/nodes/3/drive/enable", headers={"X-Client-Id": "t"})
    assert enabled.json()["state"] == "operation_enabled"
    with client.websocket_connect("/api/ws") as ws:
        ws.send_json({"type": "quick_stop", "node": 3, "value": LINK})
        ws.send_json({"type": "ping"})
        while (message := ws.receive_json())["type"] not in ("pong", "error"):
            pass
        assert message["type"] == "pong"
    for _ in range(100):  # the stop runs on a task of its own
        state = client.get("/api/nodes/3/drive").json()["state"]
        if state != "operation_enabled":
            break
        time.sleep(0.02)
    assert state in {"quick_stop_active", "switch_on_disabled"}
