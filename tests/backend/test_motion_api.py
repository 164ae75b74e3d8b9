"""The drive, controller, jog and quick-stop routes: paths, fields and statuses as documented
(docs/api.md, Drive and Jog), against the simulated drives."""

from __future__ import annotations

from typing import Any

import httpx
from fastapi.testclient import TestClient

A = {"X-Client-Id": "page-a", "X-Client-Name": "Alice"}
B = {"X-Client-Id": "page-b"}


def ok(response: httpx.Response, status: int = 200) -> Any:
    assert response.status_code == status, response.text
    return response.json()


def error_of(response: httpx.Response, status: int) -> dict[str, Any]:
    assert response.status_code == status, response.text
    body: dict[str, Any] = response.json()
    assert set(body) >= {"error", "message"}
    return body


def test_drive_state_and_the_state_machine_routes(client: TestClient) -> None:
    state = ok(client.get("/api/nodes/3/drive"))
    assert state["node"] == 3
    assert "statusword" in state
    assert "limits" in state
    assert ok(client.post("/api/nodes/3/drive/enable", headers=A))["state"] == "operation_enabled"
    assert ok(client.post("/api/nodes/3/drive/disable", headers=A))["state"] != "operation_enabled"
    assert ok(client.post("/api/nodes/3/drive/fault-reset", headers=A))["node"] == 3
    assert ok(client.post("/api/nodes/3/drive/quick-stop", headers=B))["node"] == 3
    error_of(client.get("/api/nodes/99/drive"), 404)


def test_a_command_that_is_not_a_name_is_refused_not_a_server_error(client: TestClient) -> None:
    for body in ({"command": {"quick_stop": 1}}, {"command": ["quick_stop"]}, {"command": 7}):
        refused = error_of(client.post("/api/nodes/1/drive/command", headers=A, json=body), 422)
        assert refused["error"] == "invalid_request", refused


def test_enable_blocked_names_the_reasons(client: TestClient) -> None:
    ok(client.post("/api/nodes/2/nmt", json={"command": "stop"}))
    body = error_of(client.post("/api/nodes/2/drive/enable", headers=A), 409)
    assert body["error"] == "enable_blocked"
    assert body["reasons"]
    assert {"code", "message"} <= set(body["reasons"][0])
    assert body["state"]["node"] == 2


def test_moves_homing_and_limits(client: TestClient) -> None:
    ok(client.post("/api/nodes/3/drive/enable", headers=A))
    move = {"position_rev": 0.5, "relative": True, "velocity_rpm": 300}
    assert ok(client.post("/api/nodes/3/drive/move", headers=A, json=move), 202)["node"] == 3
    queue = {"moves": [move, move]}
    ok(client.post("/api/nodes/3/drive/move-queue", headers=A, json=queue), 202)
    methods = ok(client.get("/api/nodes/3/drive/homing-methods"))
    assert methods
    assert {"method", "name", "description", "path"} <= set(methods[0])
    limits = ok(client.get("/api/nodes/3/drive/limits"))
    limits["max_velocity_rpm"] = 1000
    assert ok(client.put("/api/nodes/3/drive/limits", headers=A, json=limits)) == limits
    too_fast = {"mode": "pv", "velocity_rpm": 2000, "keepalive_ms": 200}
    assert error_of(client.post("/api/nodes/3/jog", headers=A, json=too_fast), 422)
    home = {"method": methods[0]["method"]}
    assert ok(client.post("/api/nodes/3/drive/home", headers=A, json=home), 202)["node"] == 3


def test_controller_lease(client: TestClient) -> None:
    free = ok(client.get("/api/nodes/1/drive/controller", headers=A))
    assert free["holder"] is None
    assert free["you"] is False
    taken = ok(client.post("/api/nodes/1/drive/controller", headers=A, json={}))
    assert taken["you"]
    assert taken["holder"]["name"] == "Alice"
    assert set(taken["protection"]) == {"active", "tool_node_id", "consumer_ms", "message"}
    seen = ok(client.get("/api/nodes/1/drive/controller", headers=B))
    assert seen["you"] is False
    assert seen["holder"]["client_id"] == "page-a"
    refused = error_of(client.post("/api/nodes/1/drive/enable", headers=B), 409)
    assert refused["error"] == "held_by_other"
    assert refused["holder"]["name"] == "Alice"
    refused = error_of(client.post("/api/nodes/1/drive/enable"), 409)  # a script, too
    assert refused["error"] == "held_by_other"
    error_of(client.post("/api/nodes/1/drive/controller", headers=B, json={}), 409)
    # quick stop by anyone
    ok(client.post("/api/nodes/1/drive/quick-stop", headers=B))
    ok(client.post("/api/quick-stop"))
    over = ok(client.post("/api/nodes/1/drive/controller", headers=B, json={"take_over": True}))
    assert over["holder"]["client_id"] == "page-b"
    error_of(client.delete("/api/nodes/1/drive/controller", headers=A), 409)
    released = ok(client.delete("/api/nodes/1/drive/controller", headers=B))
    assert released["holder"] is None
    error_of(client.post("/api/nodes/1/drive/controller", json={}), 422)  # needs a client id


def test_jog_routes(client: TestClient) -> None:
    ok(client.post("/api/nodes/2/drive/enable", headers=A))
    body = {"mode": "pv", "velocity_rpm": 300, "keepalive_ms": 500}
    jog = ok(client.post("/api/nodes/2/jog", headers=A, json=body))
    assert jog["state"] == "running"
    assert jog["node"] == 2
    assert jog["owner"] == "page-a"
    assert ok(client.post(f"/api/jog/{jog['jog_id']}/keepalive"))["state"] == "running"
    stopped = ok(client.delete(f"/api/jog/{jog['jog_id']}"))
    assert stopped["state"] == "stopping"  # the stop went out; the axis still decelerates
    assert stopped["stop_reason"] == "stopped by the user"
    assert stopped["stop_deceleration_rpm_s"] >= 1000  # never slower than ServoDesk's floor
    again = error_of(client.post(f"/api/jog/{jog['jog_id']}/keepalive"), 409)
    assert again["error"] == "jog_stopped"
    assert again["jog"]["jog_id"] == jog["jog_id"]
    assert error_of(client.get("/api/jog/nope"), 404)["error"] == "jog_not_found"
    slow = {"mode": "pv", "velocity_rpm": 300, "keepalive_ms": 600}
    error_of(client.post("/api/nodes/2/jog", headers=A, json=slow), 422)
    wrong = {"mode": "pt", "velocity_rpm": 300}
    assert error_of(client.post("/api/nodes/2/jog", headers=A, json=wrong), 422)
    refused = error_of(client.post("/api/nodes/2/jog", headers=B, json=body), 409)
    assert refused["error"] == "held_by_other"
