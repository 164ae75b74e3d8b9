"""The typed two-way WebSocket: hello owns the socket, keep-alives feed the jog watchdog,
closing the socket stops the owner's jogs, drive state and controller messages arrive, and every
message matches its model in the OpenAPI schema."""

from __future__ import annotations

from typing import Any

from fastapi.testclient import TestClient
from starlette.testclient import WebSocketTestSession

from servodesk.models.live import CLIENT_MESSAGE, ServerMessage

PAGE = {"X-Client-Id": "page-a", "X-Client-Name": "Alice"}


def receive_until(ws: WebSocketTestSession, kind: str, limit: int = 500) -> dict[str, Any]:
    for _ in range(limit):
        message: dict[str, Any] = ws.receive_json()
        ServerMessage.model_validate(message)  # every message is one of the typed ones
        if message["type"] == kind:
            return message
    raise AssertionError(f"no {kind} message")


def start_jog(client: TestClient, node: int) -> str:
    assert client.post(f"/api/nodes/{node}/drive/enable", headers=PAGE).status_code == 200
    body = {"mode": "pv", "velocity_rpm": 300, "keepalive_ms": 500}
    answer = client.post(f"/api/nodes/{node}/jog", headers=PAGE, json=body)
    assert answer.status_code == 200, answer.text
    jog_id: str = answer.json()["jog_id"]
    return jog_id


def test_messages_are_in_the_schema(client: TestClient) -> None:
    schemas = client.get("/api/openapi.json").json()["components"]["schemas"]
    for name in ("ServerMessage", "ClientMessage", "DriveStateMessage", "HelloMessage"):
        assert name in schemas
    mapping = schemas["ServerMessage"]["discriminator"]["mapping"]
    assert {"bus", "nodes", "event", "history", "pong", "drive_state", "controller"} <= set(mapping)
    for message in (
        {"type": "hello", "client_id": "a"},
        {"type": "jog_keepalive", "jog_id": "x"},
        {"type": "jog_stop", "jog_id": "x"},
        {"type": "page_hidden"},
        {"type": "quick_stop", "node": 3},
        {"type": "watch_drive", "node": 3},
    ):
        assert CLIENT_MESSAGE.validate_python(message).type == message["type"]


def test_watch_drive_sends_state_and_controller(client: TestClient) -> None:
    with client.websocket_connect("/api/ws") as ws:
        ws.send_json({"type": "hello", "client_id": "page-a", "name": "Alice"})
        ws.send_json({"type": "watch_drive", "node": 3})
        assert receive_until(ws, "controller")["holder"] is None  # at once, then the states
        state = receive_until(ws, "drive_state")
        assert state["node"] == 3
        assert state["state"]["node"] == 3
        client.post("/api/nodes/3/drive/controller", headers=PAGE, json={})
        controller = receive_until(ws, "controller")
        assert controller["you"] is True
        assert controller["holder"]["name"] == "Alice"
        ws.send_json({"type": "nonsense"})
        assert receive_until(ws, "error")["error"] == "invalid_message"


def test_keepalives_over_the_socket_and_its_close_stops_the_jog(client: TestClient) -> None:
    with client.websocket_connect("/api/ws") as ws:
        ws.send_json({"type": "hello", "client_id": "page-a"})
        ws.send_json({"type": "ping"})
        receive_until(ws, "pong")  # the hello was handled before
        jog_id = start_jog(client, 2)
        for _ in range(3):
            ws.send_json({"type": "jog_keepalive", "jog_id": jog_id})
            ws.send_json({"type": "ping"})
            receive_until(ws, "pong")
        assert client.get(f"/api/jog/{jog_id}").json()["state"] == "running"
    stopped = wait_stopped(client, jog_id)
    assert stopped["stop_reason"] == "the page's connection closed"


def test_page_hidden_and_jog_stop_messages(client: TestClient) -> None:
    with client.websocket_connect("/api/ws") as ws:
        ws.send_json({"type": "hello", "client_id": "page-a"})
        ws.send_json({"type": "watch_drive", "node": 1})
        receive_until(ws, "controller")
        jog_id = start_jog(client, 1)
        ws.send_json({"type": "page_hidden"})
        message = receive_until(ws, "jog_stopped")
        assert message["jog"]["jog_id"] == jog_id
        assert message["jog"]["stop_reason"] == "the page was hidden"
        ws.send_json({"type": "jog_keepalive", "jog_id": jog_id})  # too late: told so
        assert receive_until(ws, "jog_stopped")["jog"]["state"] in ("stopping", "stopped")
        second = start_jog(client, 1)
        ws.send_json({"type": "jog_stop", "jog_id": second})
        message = receive_until(ws, "jog_stopped")
        while message["jog"]["jog_id"] != second:  # the first jog's axis coming to rest
            message = receive_until(ws, "jog_stopped")
        assert message["jog"]["stop_reason"] == "stopped by the user"
        ws.send_json({"type": "quick_stop", "node": 1})
        ws.send_json({"type": "ping"})
        receive_until(ws, "pong")
    assert client.get("/api/nodes/1/drive").json()["state"] != "operation_enabled"


def wait_stopped(client: TestClient, jog_id: str) -> dict[str, Any]:
    for _ in range(1000):
        info: dict[str, Any] = client.get(f"/api/jog/{jog_id}").json()
        if info["state"] == "stopped":
            return info
    raise AssertionError("the jog did not stop")
