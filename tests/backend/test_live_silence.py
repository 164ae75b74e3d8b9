"""A page that vanishes without closing its socket (a killed tab, a sleeping laptop) releases the
drives it controls once its socket has been silent for `live_silence_s`: pages ping every 10 s,
so silence means gone. A socket that pings stays."""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi.testclient import TestClient
from starlette.testclient import WebSocketTestSession
from starlette.websockets import WebSocketDisconnect

from servodesk.app import create_app
from servodesk.settings import Settings

TAB = {"X-Client-Id": "tab-1", "X-Client-Name": "Chrome tab 1"}


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path, live_silence_s=0.6)
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


def holder(client: TestClient) -> object:
    return client.get("/api/nodes/3/drive/controller").json()["holder"]


def closing(ws: WebSocketTestSession) -> WebSocketDisconnect:
    """Read until the server closes the socket."""
    while True:
        try:
            ws.receive_json()
        except WebSocketDisconnect as closed:
            return closed


def test_a_silent_page_is_closed_and_its_drives_released(client: TestClient) -> None:
    with client.websocket_connect("/api/ws") as ws:
        ws.send_json({"type": "hello", "client_id": "tab-1", "name": "Chrome tab 1"})
        taken = client.post("/api/nodes/3/drive/controller", headers=TAB, json={})
        assert taken.status_code == 200, taken.text
        assert holder(client) is not None
        for _ in range(3):  # pinging keeps it: 3 × 0.3 s is longer than the silence limit
            ws.send_json({"type": "ping"})
            time.sleep(0.3)
        assert holder(client) is not None
        closed = closing(ws)  # then silence
        assert closed.code == 1001
        assert "nothing received for 0.6 s" in (closed.reason or "")
    for _ in range(100):
        if holder(client) is None:
            break
        time.sleep(0.02)
    assert holder(client) is None  # released: another tab may take it without taking over
