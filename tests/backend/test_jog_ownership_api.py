"""Control bound to its owner, through the real app with tokens configured: a viewer's socket
can neither keep an operator's jog moving nor borrow the operator's client id (and so release
its control and heartbeat protection, or hide its page); stopping stays open to everyone."""

from __future__ import annotations

import time
from collections.abc import Iterator
from typing import Any

import pytest
from fastapi.testclient import TestClient
from pydantic import SecretStr
from starlette.testclient import WebSocketTestSession

from servodesk.app import create_app
from servodesk.settings import Settings

ENGINEER = "eng-secret-0123456789"
OPERATOR = "op-secret-0123456789"
VIEWER = "view-secret-0123456789"
TOKENS = f"engineer={ENGINEER},operator={OPERATOR},viewer={VIEWER}"
NODE = 3
PAGE = {"X-Client-Id": "operator-tab", "X-Client-Name": "operator's tab"}


def bearer(token: str, **more: str) -> dict[str, str]:
    return {"authorization": f"Bearer {token}", **more}


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    settings = Settings(
        simulated=True, data_dir=tmp_path_factory.mktemp("data"), tokens=SecretStr(TOKENS)
    )
    with TestClient(create_app(settings, static_dir=None)) as client:
        yield client


def ok(response: Any) -> Any:
    assert response.status_code < 300, response.text
    return response.json()


def answer(ws: WebSocketTestSession, kinds: tuple[str, ...]) -> dict[str, Any]:
    ws.send_json({"type": "ping"})
    while (message := ws.receive_json())["type"] not in (*kinds, "pong"):
        pass
    return dict(message)


def start_jog(client: TestClient) -> str:
    operator = bearer(OPERATOR, **PAGE)
    for index, rev in ((0x5FF1, -1000), (0x5FF2, 1000)):  # limit switches out of the way
        path = f"/api/nodes/{NODE}/sdo/{index:04X}/0"
        ok(client.put(path, headers=bearer(ENGINEER), json={"value": rev * 131072}))
    ok(client.post(f"/api/nodes/{NODE}/drive/enable", headers=operator))
    body = {"mode": "pv", "velocity_rpm": 200, "keepalive_ms": 300}
    jog_id: str = ok(client.post(f"/api/nodes/{NODE}/jog", headers=operator, json=body))["jog_id"]
    return jog_id


def test_a_viewer_s_keepalives_do_not_keep_an_operator_s_jog_moving(client: TestClient) -> None:
    client.cookies.clear()
    jog_id = start_jog(client)
    ok(client.post("/api/login", json={"token": VIEWER}))
    with client.websocket_connect("/api/ws") as ws:
        ws.send_json({"type": "hello", "client_id": "viewer-tab"})
        deadline = time.monotonic() + 3
        refused = None
        while time.monotonic() < deadline:
            ws.send_json({"type": "jog_keepalive", "jog_id": jog_id})
            message = answer(ws, ("error", "jog_stopped"))
            if message["type"] == "error":
                refused = message
            state = ok(client.get(f"/api/jog/{jog_id}"))["state"]
            if state != "running":
                break
            time.sleep(0.05)
        assert refused is not None, "the viewer's keep-alives were taken"
        assert refused["error"] == "not_jog_owner", refused
        stopped = ok(client.get(f"/api/jog/{jog_id}"))
        assert stopped["state"] != "running", "the viewer kept the operator's axis moving"
        assert stopped["stop_reason"].startswith("keep-alive missed")
    client.cookies.clear()


def test_a_viewer_cannot_say_hello_as_the_operator_s_page(client: TestClient) -> None:
    client.cookies.clear()
    operator = bearer(OPERATOR, **PAGE)
    ok(client.post(f"/api/nodes/{NODE}/drive/controller", headers=operator, json={}))
    ok(client.post("/api/login", json={"token": VIEWER}))
    with client.websocket_connect("/api/ws") as ws:
        ws.send_json({"type": "hello", "client_id": PAGE["X-Client-Id"]})
        refused = answer(ws, ("error",))
        assert refused.get("error") == "client_id_taken", refused
        ws.send_json({"type": "page_hidden"})
    client.cookies.clear()
    held = ok(client.get(f"/api/nodes/{NODE}/drive/controller", headers=operator))
    assert held["you"], "the viewer's closed socket released the operator's control"
    assert held["protection"]["active"], held["protection"]
    ok(client.delete(f"/api/nodes/{NODE}/drive/controller", headers=operator))


def test_another_login_cannot_use_a_held_client_id_over_rest(client: TestClient) -> None:
    """An engineer's script that sends the operator page's id does not act as that page."""
    client.cookies.clear()
    operator = bearer(OPERATOR, **PAGE)
    ok(client.post(f"/api/nodes/{NODE}/drive/controller", headers=operator, json={}))
    path = f"/api/nodes/{NODE}/drive/controller"
    taken = client.delete(path, headers=bearer(ENGINEER, **PAGE))
    assert (taken.status_code, taken.json()["error"]) == (403, "client_id_taken"), taken.text
    assert ok(client.get(path, headers=operator))["you"]
    ok(client.delete(path, headers=operator))
