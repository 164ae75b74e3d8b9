"""POST …/drive/command: one CiA 402 controlword per button, behind the controller lease, with
"why not" when the transition does not happen; strict request bodies; the jog's ramp and the
PT speed limit; the statusword hook that publishes state changes. Against the simulated drives
(1 MDi-S1-C, 2 Kinco, 3 CiA 402)."""

from __future__ import annotations

import time
from typing import Any

import httpx
import pytest
from fastapi.testclient import TestClient

from servodesk.motion.service import MotionService
from tests.backend.motion_rig import CIA402, NODES, SIM_INJECT_FAULT, motion_rig, motion_settings

A = {"X-Client-Id": "page-a", "X-Client-Name": "Alice"}
B = {"X-Client-Id": "page-b"}


def ok(response: httpx.Response, status: int = 200) -> Any:
    assert response.status_code == status, response.text
    return response.json()


def command(client: TestClient, node: int, name: str, headers: dict[str, str] = A) -> Any:
    return client.post(f"/api/nodes/{node}/drive/command", headers=headers, json={"command": name})


def sdo(client: TestClient, node: int, index: int, sub: int = 0) -> int:
    value: int = ok(client.get(f"/api/nodes/{node}/sdo/{index:04X}/{sub}"))["value"]
    return value


def to_switch_on_disabled(client: TestClient, node: int) -> None:
    if ok(client.get(f"/api/nodes/{node}/drive"))["state"] != "switch_on_disabled":
        ok(command(client, node, "disable_voltage"))


@pytest.mark.parametrize("node", NODES)
def test_each_button_takes_its_transition_with_its_controlword(
    client: TestClient, node: int
) -> None:
    to_switch_on_disabled(client, node)
    steps = [
        ("shutdown", 0x0006, "ready_to_switch_on", "shutdown (2)"),
        ("switch_on", 0x0007, "switched_on", "switch on (3)"),
        ("enable_operation", 0x000F, "operation_enabled", "enable operation (4)"),
        ("disable_operation", 0x0007, "switched_on", "disable operation (5)"),
        ("enable_operation", 0x000F, "operation_enabled", "enable operation (4)"),
        ("shutdown", 0x0006, "ready_to_switch_on", "shutdown (8)"),
        ("disable_voltage", 0x0000, "switch_on_disabled", "disable voltage (7)"),
    ]
    for name, word, state, taken in steps:
        after = ok(command(client, node, name))
        assert (after["state"], after["controlword"], after["last_transition"]) == (
            state,
            word,
            taken,
        )
        assert sdo(client, node, 0x6040) == word  # what the drive holds in 6040h


def test_quick_stop_is_open_to_all_and_writes_0002h(client: TestClient) -> None:
    ok(client.post(f"/api/nodes/{CIA402}/drive/enable", headers=A))
    stopped = ok(command(client, CIA402, "quick_stop", headers=B))  # B holds nothing
    assert stopped["controlword"] == 0x0002
    assert stopped["state"] in ("quick_stop_active", "switch_on_disabled")
    refused = command(client, CIA402, "shutdown", headers=B)
    assert refused.status_code == 409
    assert refused.json()["error"] == "held_by_other"
    assert refused.json()["holder"]["name"] == "Alice"


def test_a_command_with_no_transition_sends_nothing_and_says_why(client: TestClient) -> None:
    to_switch_on_disabled(client, CIA402)
    refused = command(client, CIA402, "switch_on")
    assert refused.status_code == 409
    body = refused.json()
    assert body["error"] == "enable_blocked"
    assert body["reasons"][0]["code"] == "no_transition"
    assert "Ready to switch on (3)" in body["reasons"][0]["message"]
    assert body["state"]["state"] == "switch_on_disabled"
    assert sdo(client, CIA402, 0x6040) == 0x0000  # 0007h was never written


def test_in_fault_the_explainer_names_the_fault_and_fault_reset_clears_it(
    client: TestClient,
) -> None:
    ok(client.put(f"/api/nodes/{CIA402}/sdo/{SIM_INJECT_FAULT:04X}/0", json={"value": 0x8611}))
    deadline = time.monotonic() + 2
    while ok(client.get(f"/api/nodes/{CIA402}/drive"))["state"] != "fault":
        assert time.monotonic() < deadline
        time.sleep(0.02)
    refused = command(client, CIA402, "shutdown")
    assert refused.status_code == 409
    codes = [reason["code"] for reason in refused.json()["reasons"]]
    assert codes[:2] == ["no_transition", "fault"]
    after = ok(command(client, CIA402, "fault_reset"))
    assert after["state"] == "switch_on_disabled"
    assert after["controlword"] == 0x0000  # bit 7 back to 0 after the 0 -> 1 edge


def test_unknown_commands_and_non_text_are_refused(client: TestClient) -> None:
    for body in ({"command": "power_on"}, {"command": 6}, {}, {"command": "shutdown", "x": 1}):
        response = client.post(f"/api/nodes/{CIA402}/drive/command", headers=A, json=body)
        assert response.status_code == 422, body


# ---------------------------------------------------------------------------- strict bodies

MOVE = {"position_rev": 0.5, "velocity_rpm": 300}
IP = {"trajectory": "sine", "period_ms": 4, "distance_rev": 1, "duration_s": 1}


@pytest.mark.parametrize(
    ("path", "body"),
    [
        ("drive/move", {**MOVE, "position_rev": "0.5"}),
        ("drive/move", {**MOVE, "velocity_rpm": True}),
        ("drive/move", {**MOVE, "relative": "true"}),
        ("drive/move", {**MOVE, "relative": 1}),
        ("drive/move", {**MOVE, "acceleration_rpm_s": "1000"}),
        ("drive/move", {**MOVE, "immediately": 0}),
        ("drive/move-queue", {"moves": [MOVE, {**MOVE, "velocity_rpm": "300"}]}),
        ("drive/home", {"method": 35, "fast_rpm": "100"}),
        ("drive/home", {"method": 35, "slow_rpm": False}),
        ("drive/home", {"method": "35"}),
        ("drive/ip-stream", {**IP, "distance_rev": "1"}),
        ("drive/ip-stream", {**IP, "duration_s": True}),
        ("jog", {"mode": "pv", "velocity_rpm": "60"}),
        ("jog", {"mode": "pv", "velocity_rpm": 60, "acceleration_rpm_s": "500"}),
        ("jog", {"mode": "pv", "velocity_rpm": 60, "acceleration_rpm_s": True}),
        ("jog", {"mode": "pv", "velocity_rpm": 60, "acceleration_rpm_s": 0}),
        ("jog", {"mode": "pt", "torque_pct": 5, "torque_slope_pct_s": "1000"}),
        ("jog", {"mode": "pt", "torque_pct": 5, "torque_slope_pct_s": 50}),  # below one step
        ("jog", {"mode": "pt", "torque_pct": 5, "acceleration_rpm_s": 500}),  # pv's field
        ("jog", {"mode": "pv", "velocity_rpm": 60, "torque_slope_pct_s": 1000}),  # pt's field
    ],
)
def test_request_numbers_are_json_numbers(client: TestClient, path: str, body: Any) -> None:
    ok(client.post(f"/api/nodes/{CIA402}/drive/enable", headers=A))
    response = client.post(f"/api/nodes/{CIA402}/{path}", headers=A, json=body)
    assert response.status_code == 422, response.text
    assert ok(client.get(f"/api/nodes/{CIA402}/drive"))["move"] is None  # nothing moved


# ---------------------------------------------------------------------------- jog ramps


def map_recommended(client: TestClient, node: int, modes: str) -> None:
    """The manuals' recommended PDOs for `modes`, applied, the node Operational: the drive
    state then comes from its TPDOs."""
    ok(client.post(f"/api/nodes/{node}/nmt", json={"command": "start"}))
    wanted = ok(client.get(f"/api/nodes/{node}/pdos/recommended", params={"modes": modes}))
    ok(client.put(f"/api/nodes/{node}/pdos", json={"pdos": wanted["pdos"]}))


def test_pv_jog_runs_at_the_chosen_acceleration(client: TestClient) -> None:
    map_recommended(client, CIA402, "pv")  # the page sees 606Ch in a TPDO, as it changes
    ok(client.post(f"/api/nodes/{CIA402}/drive/enable", headers=A))
    body = {"mode": "pv", "velocity_rpm": 300, "acceleration_rpm_s": 600, "keepalive_ms": 500}
    jog = ok(client.post(f"/api/nodes/{CIA402}/jog", headers=A, json=body))
    assert jog["acceleration_rpm_s"] == 600
    assert jog["torque_slope_pct_s"] is None
    # 6083h/6084h in user units/s per ms: 600 rpm/s = 10 rev/s², 100 000 user units per rev
    assert sdo(client, CIA402, 0x6083) == sdo(client, CIA402, 0x6084) == 1000
    # the ramp as the page sees it: velocity against the time of each reading (the middle of
    # its request), fitted over the readings between standstill and the set speed, so a slow
    # host (late requests) does not count as a faster ramp
    samples: list[tuple[float, float]] = []
    sources: set[str] = set()
    deadline = time.monotonic() + 3
    while time.monotonic() < deadline:
        ok(client.post(f"/api/jog/{jog['jog_id']}/keepalive"))
        before = time.monotonic()
        state = ok(client.get(f"/api/nodes/{CIA402}/drive"))
        speed = state["velocity_rpm"]
        samples.append(((before + time.monotonic()) / 2, speed))
        sources.add(state["sources"]["velocity"] if 20 < speed < 280 else "")
        if speed >= 280:
            break
    ramp = [(t, v) for t, v in samples if 20 < v < 280]
    assert len(ramp) >= 4, samples
    assert sources - {""} == {"TPDO1"}  # every reading on the ramp came from the frames
    mean_t = sum(t for t, _ in ramp) / len(ramp)
    mean_v = sum(v for _, v in ramp) / len(ramp)
    slope = sum((t - mean_t) * (v - mean_v) for t, v in ramp) / sum(
        (t - mean_t) ** 2 for t, _ in ramp
    )
    # 600 rpm/s, well apart from the 1000 rpm/s default ramp
    assert 420 < slope < 800, (slope, samples)
    ok(client.delete(f"/api/jog/{jog['jog_id']}"))


def test_pt_jog_takes_its_slope_and_the_drive_caps_the_speed(client: TestClient) -> None:
    ok(client.put(f"/api/nodes/{CIA402}/sdo/6080/0", json={"value": 200}))  # Max motor speed
    ok(client.post(f"/api/nodes/{CIA402}/drive/enable", headers=A))  # reads 6080h again
    body = {"mode": "pt", "torque_pct": 30, "torque_slope_pct_s": 1000, "keepalive_ms": 500}
    jog = ok(client.post(f"/api/nodes/{CIA402}/jog", headers=A, json=body))
    assert jog["torque_slope_pct_s"] == 1000
    assert jog["velocity_limit_rpm"] == 200
    assert jog["velocity_limit_source"] == "6080h Max motor speed"
    assert sdo(client, CIA402, 0x6087) == 10  # 0.1 %/ms
    started = time.monotonic()
    fastest = 0.0
    # a second at least, longer (up to 3 s) on a host too busy to get there in a second
    while (elapsed := time.monotonic() - started) < 1.0 or (fastest < 190 and elapsed < 3.0):
        ok(client.post(f"/api/jog/{jog['jog_id']}/keepalive"))
        fastest = max(fastest, abs(ok(client.get(f"/api/nodes/{CIA402}/drive"))["velocity_rpm"]))
    assert 150 < fastest <= 201  # up at the limit, never past it
    ok(client.delete(f"/api/jog/{jog['jog_id']}"))


def test_pt_speed_limit_on_the_mdi_is_pa_103(client: TestClient) -> None:
    ok(client.post("/api/nodes/1/drive/enable", headers=A))
    body = {"mode": "pt", "torque_pct": 1, "keepalive_ms": 500}
    jog = ok(client.post("/api/nodes/1/jog", headers=A, json=body))
    assert jog["velocity_limit_rpm"] == sdo(client, 1, 0x2006, 8)
    assert jog["velocity_limit_source"] == "2006h:08 PA-103 Maximum speed"
    assert jog["torque_slope_pct_s"] == 100  # the default: 6087h = 1
    ok(client.delete(f"/api/jog/{jog['jog_id']}"))


# ---------------------------------------------------------------------------- statusword hook


@pytest.mark.anyio
async def test_every_statusword_read_reaches_the_hook() -> None:
    async with motion_rig() as r:
        seen: list[tuple[int, int]] = []
        motion = MotionService(
            r.rig.registry, motion_settings(), on_statusword=lambda n, s: seen.append((n, s))
        )
        await motion.enable(CIA402)
        assert seen
        assert {node for node, _ in seen} == {CIA402}
        assert seen[-1][1] & 0x6F == 0x27  # the last read shows Operation enabled
        await motion.stop(CIA402, reason="test")  # the priority lane's read, too
        assert len(seen) > 1


def test_state_changes_are_published_as_events(client: TestClient) -> None:
    ok(client.post(f"/api/nodes/{CIA402}/drive/enable", headers=A))
    ok(command(client, CIA402, "disable_operation"))
    events = ok(client.get("/api/events", params={"node": CIA402, "kind": "cia402-state"}))
    rows = events["events"]
    texts = " | ".join(row["message"] for row in rows)
    assert "Operation enabled" in texts
    assert "Switched on" in texts
