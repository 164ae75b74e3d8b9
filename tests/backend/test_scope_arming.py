"""A triggered capture says `arming` until it can see its trigger, then `armed`: a user who
acts on "armed" does not act too early. Over a real capture on the simulated drives, through
the API: arming → armed → running (the drive enabled: the state trigger fires) → done."""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.settings import Settings

CLIENT = {"X-Client-Id": "scope-arming-test"}
POSITION = 0x6064


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path, scope_live_view=False)
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


def ok(response: httpx.Response) -> Any:
    assert response.status_code == 200, response.text
    return response.json()


def states_until(client: TestClient, capture_id: int, last: set[str]) -> list[str]:
    """The capture's states as GET shows them, each change once, until one of `last`."""
    seen: list[str] = []
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:
        state = ok(client.get(f"/api/scope/captures/{capture_id}"))["state"]
        if not seen or seen[-1] != state:
            seen.append(state)
        if state in last:
            return seen
        time.sleep(0.01)
    raise AssertionError(f"capture {capture_id} never reached {last}: {seen}")


def test_a_state_triggered_capture_goes_arming_armed_running_done(client: TestClient) -> None:
    # the app's start-up work done before the drive watches ServoDesk's heartbeat
    time.sleep(0.5)
    request = {
        "signals": [{"node": 1, "index": POSITION}],
        "sync_period_us": 1000,
        "duration_s": 0.4,
        "trigger": {"kind": "state", "node": 1, "state": "operation enabled", "pre_s": 0.1},
    }
    capture = ok(client.post("/api/scope/captures", json=request))
    assert capture["state"] == "arming"  # its trigger has not seen the statusword yet
    before = states_until(client, capture["id"], {"armed", "running", "done", "failed"})
    assert before[-1] == "armed", before
    assert set(before) <= {"arming", "armed"}

    ok(client.post("/api/nodes/1/drive/enable", headers=CLIENT))
    after = states_until(client, capture["id"], {"done", "failed"})
    assert [state for state in after if state != "armed"] == ["running", "done"], after
    done = ok(client.get(f"/api/scope/captures/{capture['id']}"))
    assert done["trigger_time"] is not None
    assert done["samples"] > 0
    listed = {c["id"]: c["state"] for c in ok(client.get("/api/scope/captures"))}
    assert listed == {capture["id"]: "done"}
