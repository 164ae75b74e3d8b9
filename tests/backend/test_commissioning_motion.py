"""stop_test and test_move through the API on the simulated drives: the tool moves the axis,
captures it, and records figures a user would check; the drive is left disabled and released.

Bounds on times are generous on purpose: a stop's measured time includes the trip through the
node's queue and the (simulated) bus and the event loop's lag, which on a busy 2-core host can be
hundreds of ms beyond the ramp. Waits end on states the app reports, never on fixed sleeps."""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.settings import Settings

QUICK_STOP_DECELERATION = "6085/0"
SIM_NEG_LIMIT, SIM_POS_LIMIT = "5FF1/0", "5FF2/0"  # simulator only: limit switch positions
GENTLE_RPM_S = 3000.0  # a quick stop ramp a real machine may have: 0.1 s from 300 rpm
USER_PER_REV = 100000  # the simulated drives' default gear: 100000 user units per rev


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path, scope_live_view=False)
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


def ok(response: Any, status: int = 200) -> Any:
    assert response.status_code == status, response.text
    return response.json()


def wait_known(client: TestClient, node: int) -> None:
    """The simulated drives announce themselves as the app starts: wait for the node's boot-up
    to be seen (bounded), not a fixed time."""
    deadline = time.monotonic() + 30
    while node not in {n["node"] for n in ok(client.get("/api/nodes"))}:
        assert time.monotonic() < deadline, f"node {node} never appeared"
        time.sleep(0.02)


def prepare(client: TestClient, node: int, modes: list[str]) -> int:
    wait_known(client, node)
    # the switches out of the way (a slow host lets the jog run longer before the stop)
    ok(client.put(f"/api/nodes/{node}/sdo/{SIM_NEG_LIMIT}", json={"value": -200 * 131072}))
    ok(client.put(f"/api/nodes/{node}/sdo/{SIM_POS_LIMIT}", json={"value": 200 * 131072}))
    # 6085h in user units/s per ms: rpm/s ÷ 60 × units per rev ÷ 1000
    gentle = round(GENTLE_RPM_S / 60 * USER_PER_REV / 1000)
    ok(client.put(f"/api/nodes/{node}/sdo/{QUICK_STOP_DECELERATION}", json={"value": gentle}))
    record = ok(client.post(f"/api/nodes/{node}/commissioning", json={"modes": modes}), 201)
    return int(record["id"])


def assert_left_stopped(client: TestClient, node: int) -> None:
    drive = ok(client.get(f"/api/nodes/{node}/drive"))
    assert drive["state"] != "operation_enabled", drive["state"]
    assert abs(drive["velocity_rpm"]) < 5
    assert ok(client.get(f"/api/nodes/{node}/drive/controller"))["holder"] is None


def assert_capture(client: TestClient, capture_id: int) -> None:
    capture = ok(client.get(f"/api/scope/captures/{capture_id}"))
    assert capture["state"] == "done", capture
    assert capture["samples"] > 0


@pytest.mark.parametrize("node", [3, 1])
def test_stop_test_measures_both_stops_against_6085h(client: TestClient, node: int) -> None:
    record = prepare(client, node, ["pv", "pp"])
    step = ok(
        client.post(f"/api/commissioning/{record}/steps/stop_test/run", json={"speed_rpm": 300.0})
    )
    assert step["status"] == "done", step["reason"]
    figures = step["figures"]
    assert figures["quick_stop_speed_rpm"] == pytest.approx(300, rel=0.05)
    # 6085h at 3000 rpm/s from 300 rpm: 0.1 s and 0.25 rev
    # the CiA 402 drive's 605Ah = 2 ramps on 6085h (set to 3000 rpm/s: 0.1 s, 0.25 rev from
    # 300 rpm); the MDi's 605Ah = 1 on 6084h, the jog's own ramp (the settings' 1000 rpm/s)
    source, rpm_s = {3: ("6085h", GENTLE_RPM_S), 1: ("6084h", 1000.0)}[node]
    deceleration = step["evidence"]["deceleration"]
    assert deceleration["deceleration_object"] == source, deceleration
    assert deceleration["deceleration_rpm_s"] == pytest.approx(rpm_s, rel=0.01)
    predicted = figures["quick_stop_predicted_time_s"]
    assert predicted == pytest.approx(300 / rpm_s, rel=0.05)
    assert figures["quick_stop_predicted_distance_rev"] == pytest.approx(
        300**2 / (120 * rpm_s), rel=0.1
    )
    assert figures["quick_stop_distance_rev"] > 0
    # never faster than the ramp allows (less the SYNC spacing), never far beyond it
    assert predicted * 0.5 < figures["quick_stop_stop_time_s"] < predicted * 1.5 + 0.5
    assert 0.5 < figures["quick_stop_distance_ratio"] < 4
    # keep-alive loss: the 200 ms window at speed, then the tool's own stop
    loss = step["evidence"]["keepalive_loss"]
    assert "keep-alive missed" in loss["stop_reason"]
    assert figures["keepalive_loss_stop_time_s"] > 0.2
    assert figures["keepalive_loss_distance_rev"] > 0
    assert figures["keepalive_loss_stop_time_s"] <= loss["allowed_time_s"]
    for capture_id in step["evidence"]["capture_ids"]:
        assert_capture(client, capture_id)
    assert len(set(step["evidence"]["capture_ids"])) == 2
    # the run's own entry (its writes) and the tool's own for the node (the missed keep-alive)
    audit = {e["id"]: e for e in ok(client.get("/api/audit", params={"limit": 500}))}
    assert step["evidence"]["audit_ids"]
    assert set(step["evidence"]["audit_ids"]) <= set(audit)
    actions = {audit[i]["action"] for i in step["evidence"]["audit_ids"]}
    assert "jog-stop" in actions, actions
    assert_left_stopped(client, node)
    saved = ok(client.get(f"/api/commissioning/{record}"))
    assert next(s for s in saved["steps"] if s["key"] == "stop_test") == step


def test_test_move_jogs_each_mode_and_measures_the_pp_move(client: TestClient) -> None:
    record = prepare(client, 3, ["pv", "pt", "pp"])
    step = ok(
        client.post(f"/api/commissioning/{record}/steps/test_move/run", json={"distance": 1.0})
    )
    assert step["status"] == "done", step["reason"]
    jogs = {j["mode"]: j for j in step["evidence"]["jogs"]}
    assert set(jogs) == {"pv", "pt"}
    assert all(j["moved"] and j["stopped"] for j in jogs.values()), jogs
    move = step["evidence"]["move"]
    assert move["phase"] == "reached"
    figures = step["figures"]
    assert figures["move_distance_rev"] == pytest.approx(1.0)
    assert 0 < figures["time_to_target_s"] <= figures["settling_time_s"]
    # 1 rev at 120 rpm takes at least 0.5 s at speed
    assert figures["time_to_target_s"] > 0.4
    assert 0 <= figures["overshoot_pct"] < 5
    assert figures["peak_following_error_rev"] >= 0
    assert figures["peak_velocity_rpm"] == pytest.approx(120, rel=0.1)
    assert_capture(client, step["evidence"]["capture_ids"][0])
    assert_left_stopped(client, 3)


def test_the_run_body_is_strict_and_optional(client: TestClient) -> None:
    wait_known(client, 3)
    record = ok(client.post("/api/nodes/3/commissioning", json={"modes": ["pp"]}), 201)["id"]
    wrong = client.post(f"/api/commissioning/{record}/steps/test_move/run", json={"speed_rpm": 1.0})
    assert wrong.status_code == 422, wrong.text
    assert "does not take speed_rpm" in wrong.json()["message"]
    unknown = client.post(f"/api/commissioning/{record}/steps/stop_test/run", json={"speed": 1})
    assert unknown.status_code == 422
    text = client.post(
        f"/api/commissioning/{record}/steps/stop_test/run", json={"speed_rpm": "300"}
    )
    assert text.status_code == 422
    # no body: the reading steps run as before
    assert ok(client.post(f"/api/commissioning/{record}/steps/identity/run"))["status"] == "done"
