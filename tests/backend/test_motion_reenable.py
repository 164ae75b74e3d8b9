"""Enabling a drive never starts it moving, and a torque jog stays inside what the drive
takes. After a quick stop during a PV or PT jog, 60FFh / 6071h still hold the jog's set-point,
and a drive follows them the moment it is in Operation enabled: every enable writes them to 0
first (found by bench/soak.py: an axis ran away)."""

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

CLIENT = {"X-Client-Id": "reenable"}


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path, scope_live_view=False)
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


def ok(response: httpx.Response) -> Any:
    assert response.status_code == 200, response.text
    return response.json()


def velocity(client: TestClient, node: int) -> int:
    value: int = ok(client.get(f"/api/nodes/{node}/sdo/606C/0"))["value"]
    return value


@pytest.mark.parametrize(
    ("node", "jog"),
    [
        (3, {"mode": "pv", "velocity_rpm": 600, "keepalive_ms": 500}),
        # the cap far above the 50 rpm looked for: a late reading must not find it passed
        (2, {"mode": "pt", "torque_pct": 30, "speed_cap_rpm": 2000.0, "keepalive_ms": 500}),
    ],
)
def test_enable_after_a_quick_stop_does_not_start_the_axis(
    client: TestClient, node: int, jog: dict[str, Any]
) -> None:
    for index, rev in ((0x5FF1, -1000), (0x5FF2, 1000)):  # limit switches out of the way
        ok(client.put(f"/api/nodes/{node}/sdo/{index:04X}/0", json={"value": rev * 131072}))
    ok(client.post(f"/api/nodes/{node}/drive/enable", headers=CLIENT))
    started = ok(client.post(f"/api/nodes/{node}/jog", headers=CLIENT, json=jog))
    deadline = time.monotonic() + 3
    while abs(velocity(client, node)) < 50:  # moving
        assert time.monotonic() < deadline, "the jog did not move the axis"
        ok(client.post(f"/api/jog/{started['jog_id']}/keepalive"))
        time.sleep(0.05)
    ok(client.post(f"/api/nodes/{node}/drive/quick-stop", headers=CLIENT))
    deadline = time.monotonic() + 8
    while abs(velocity(client, node)) > 0:
        assert time.monotonic() < deadline, "the quick stop did not stop the axis"
        time.sleep(0.1)

    state = ok(client.post(f"/api/nodes/{node}/drive/enable", headers=CLIENT))
    assert state["state"] == "operation_enabled"
    time.sleep(1.0)  # a drive holding the old set-point would be at speed by now
    assert velocity(client, node) == 0
    assert ok(client.get(f"/api/nodes/{node}/sdo/60FF/0"))["value"] == 0
    assert ok(client.get(f"/api/nodes/{node}/sdo/6071/0"))["value"] == 0


def test_the_torque_limit_follows_the_target_torques_range(client: TestClient) -> None:
    """MDi-S1-C: 6072h allows 300 % but 6071h takes ±1000 (100 %): a PT jog past it would be
    refused by the drive (abort 06090031h), so the limit the page offers stops at 100 %."""
    assert ok(client.get("/api/nodes/1/drive"))["limits"]["max_torque_pct"] == 100
    assert ok(client.get("/api/nodes/2/drive"))["limits"]["max_torque_pct"] == 300
    too_much = {"mode": "pt", "torque_pct": 150, "keepalive_ms": 500}
    ok(client.post("/api/nodes/1/drive/enable", headers=CLIENT))
    refused = client.post("/api/nodes/1/jog", headers=CLIENT, json=too_much)
    assert refused.status_code == 422, refused.text
