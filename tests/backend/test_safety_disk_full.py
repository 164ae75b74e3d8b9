"""With the data directory's file system full, stops and disables still go out and answer what
they did; the audit failure is reported beside (header X-Audit-Error on REST, an
`audit_unavailable` answer on the live channel). Other writes refuse with 507
audit_unavailable and send nothing (docs/security.md, "When the audit log cannot be written").

The disk is really full: the app's data directory is a small tmpfs filled to its last byte."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.events.bus import EventKind, event
from servodesk.settings import Settings
from servodesk.storage import Storage
from tests.backend.full_disk import fill, small_filesystem
from tests.backend.test_live_channel import receive_until

A = {"X-Client-Id": "page-a", "X-Client-Name": "Alice"}
# a quick stop ends in Quick stop active, or Switch on disabled (605Ah options 0–3)
STOPPED = {"quick_stop_active", "switch_on_disabled"}
SW_OPERATION_ENABLED = 0x0004  # statusword bit 2
SW_SWITCHED_ON = 0x0002  # statusword bit 1


@pytest.fixture
def data_dir(tmp_path: Path) -> Iterator[Path]:
    with small_filesystem(tmp_path / "data") as path:
        yield path


@pytest.fixture
def app(data_dir: Path) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=data_dir)
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


def ok(response: httpx.Response) -> Any:
    assert response.status_code == 200, response.text
    return response.json()


def enable(client: TestClient, node: int) -> None:
    state = ok(client.post(f"/api/nodes/{node}/drive/enable", headers=A))
    assert state["state"] == "operation_enabled"


def audit_failure(response: httpx.Response) -> str:
    error: str = response.headers.get("X-Audit-Error", "")
    assert error.startswith("audit_unavailable"), dict(response.headers)
    return error


def test_rest_quick_stop_answers_what_it_did(app: TestClient, data_dir: Path) -> None:
    enable(app, 3)
    fill(data_dir)
    response = app.post("/api/nodes/3/drive/quick-stop")
    state = ok(response)
    assert state["state"] in STOPPED
    assert "full" in audit_failure(response)
    everything = app.post("/api/quick-stop")
    assert ok(everything)["failed"] == {}
    audit_failure(everything)


def test_websocket_quick_stop_keeps_the_socket(app: TestClient, data_dir: Path) -> None:
    enable(app, 2)
    fill(data_dir)
    with app.websocket_connect("/api/ws") as ws:
        ws.send_json({"type": "hello", "client_id": "page-b"})
        ws.send_json({"type": "quick_stop", "node": 2})
        answer = receive_until(ws, "error")
        assert answer["error"] == "audit_unavailable"
        assert "quick stop" in answer["message"]
        ws.send_json({"type": "ping"})
        receive_until(ws, "pong")  # still open and answering
    state = ok(app.get("/api/nodes/2/drive"))
    assert state["state"] in STOPPED


def test_disable_disables_the_drive(app: TestClient, data_dir: Path) -> None:
    enable(app, 1)
    fill(data_dir)
    response = app.post("/api/nodes/1/drive/disable", headers=A)
    state = ok(response)
    audit_failure(response)
    assert not state["statusword"] & SW_OPERATION_ENABLED
    polled = ok(app.get("/api/nodes/1/drive"))
    assert polled["state"] != "operation_enabled"
    assert not polled["statusword"] & SW_OPERATION_ENABLED


def test_power_down_commands_go_out(app: TestClient, data_dir: Path) -> None:
    enable(app, 3)
    fill(data_dir)
    response = app.post("/api/nodes/3/drive/command", headers=A, json={"command": "shutdown"})
    state = ok(response)
    audit_failure(response)
    assert state["state"] == "ready_to_switch_on"
    assert not state["statusword"] & SW_SWITCHED_ON


def test_other_writes_refuse_with_a_clear_error(app: TestClient, data_dir: Path) -> None:
    fill(data_dir)
    before = ok(app.get("/api/nodes/3/drive"))
    response = app.post("/api/nodes/3/drive/enable", headers=A)
    assert response.status_code == 507, response.text
    body = response.json()
    assert body["error"] == "audit_unavailable"
    assert "audit log" in body["message"]
    assert "Traceback" not in response.text
    after = ok(app.get("/api/nodes/3/drive"))
    assert after["state"] == before["state"]  # nothing was sent


@pytest.mark.anyio
async def test_the_timeline_store_starts_on_a_full_disk(data_dir: Path) -> None:
    first = Storage(data_dir)
    await first.start()
    await first.close()
    fill(data_dir)
    storage = Storage(data_dir)
    await storage.start()  # logs the failure, does not raise
    storage.add_event(event(EventKind.BUS, None, "connected"))
    await storage.flush()
    assert await storage.events() == []  # live only: nothing stored, nothing raised
    await storage.close()
