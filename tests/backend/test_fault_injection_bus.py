"""A drive that reboots mid-transfer, and a CAN adapter that is lost (bus-off, unplugged) and
comes back, seen through the API as a user sees them."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import can

from tests.backend.fault_rig import FaultyApp, faulty_app, segment_response

BOUND = 2.0  # s: the longest any answer may take here (a hang shows as far more)
NAME = {1: "DVS_CANOPEN", 2: "Kinco Servo", 3: "C5-E-SIM"}


def get(app: FaultyApp, url: str) -> tuple[int, Any]:
    answer, took = app.timed("GET", url)
    assert took < BOUND, f"GET {url} took {took:.2f} s"
    return answer.status_code, answer.json()


def events(app: FaultyApp, **query: object) -> list[dict[str, Any]]:
    status, body = get(app, "/api/events?" + "&".join(f"{k}={v}" for k, v in query.items()))
    assert status == 200, body
    found: list[dict[str, Any]] = body["events"]
    return found


def bus_state(app: FaultyApp) -> str:
    status, body = get(app, "/api/bus")
    assert status == 200, body
    state: str = body["state"]
    return state


def names_read(app: FaultyApp) -> None:
    for node, name in NAME.items():
        status, body = get(app, f"/api/nodes/{node}/sdo/1008/0")
        assert (status, body.get("value")) == (200, name), body


def test_drive_reboots_during_a_segmented_read(tmp_path: Path) -> None:
    """Expected: node 1 resets right after answering the initiate of 1008h (its segment answer
    never comes, its boot-up does): the read fails with 504 `timeout` naming node 1 and
    1008h:00h, or an abort naming node 1 and 1008h, within the bound; the timeline shows the
    boot-up; the node is listed and reads right afterwards."""
    with faulty_app(tmp_path) as app:
        boots_before = len(events(app, node=1, kind="boot-up"))
        app.rig.drop("rx", segment_response(1), times=1, then=lambda msg: app.reset_node(1))
        status, body = get(app, "/api/nodes/1/sdo/1008/0")
        assert body["node"] == 1, body
        if status == 504:
            assert body["error"] == "timeout"
            assert "1008h:00h" in body["message"]
        else:
            assert (status, body["error"], body["index"]) == (409, "sdo_abort", 0x1008), body
        app.eventually(
            lambda: len(events(app, node=1, kind="boot-up")) > boots_before, what="boot-up"
        )
        boot = events(app, node=1, kind="boot-up")[0]  # newest first
        assert boot["node"] == 1
        status, nodes = get(app, "/api/nodes")
        assert [n["node"] for n in nodes] == [1, 2, 3]
        names_read(app)


def test_adapter_lost_and_back(tmp_path: Path) -> None:
    """Expected: the adapter fails (every send and receive raises, re-opening fails): GET
    /api/health and /api/bus answer at once with state "error" and the cause; requests to
    the drives answer 503 `bus_not_connected` within the bound instead of hanging; when the
    adapter is back the manager reconnects by itself (reconnects ≥ 1), the three drives are
    listed again, read right, and the timeline has the bus error and the reconnection."""
    with faulty_app(tmp_path) as app:
        app.rig.unplug()
        app.eventually(lambda: bus_state(app) == "error", what="bus error")
        status, health = get(app, "/api/health")
        assert status == 200
        assert health["bus"]["state"] == "error"
        assert "adapter" in health["bus"]["error"], health
        assert health["bus"]["bus_errors"] >= 1
        for node in (1, 2, 3):
            status, body = get(app, f"/api/nodes/{node}/sdo/1008/0")
            assert (status, body["error"]) == (503, "bus_not_connected"), body
            assert "adapter" in body["message"] or "not connected" in body["message"], body
        # still failing to re-open: the state says it keeps trying
        app.eventually(
            lambda: "reconnecting failed" in (get(app, "/api/bus")[1]["error"] or ""),
            what="retries reported",
        )
        app.rig.plug()
        app.eventually(lambda: bus_state(app) == "connected", what="reconnection")
        status, bus = get(app, "/api/bus")
        assert bus["reconnects"] >= 1
        assert bus["error"] is None
        app.eventually(
            lambda: [n["node"] for n in get(app, "/api/nodes")[1]] == [1, 2, 3], what="nodes"
        )
        names_read(app)
        messages = [e["message"] for e in events(app, kind="bus", limit=20)]
        assert any("error" in m for m in messages), messages
        assert messages[0].startswith("bus connected"), messages  # newest first


def test_adapter_lost_in_the_middle_of_a_transfer(tmp_path: Path) -> None:
    """Expected: the adapter fails right after node 2's first segment answer of 1008h: the
    read answers 503 (`bus_not_connected` naming the adapter error, or `interrupted`) or 504
    within the bound; after the adapter is back, the read works."""
    with faulty_app(tmp_path) as app:
        app.rig.on("rx", segment_response(2), lambda msg: app.rig.unplug(), times=1)
        status, body = get(app, "/api/nodes/2/sdo/1008/0")
        assert (status, body["error"]) in {
            (503, "bus_not_connected"),
            (503, "interrupted"),
            (504, "timeout"),
        }, body
        assert body["message"]
        app.eventually(lambda: bus_state(app) == "error", what="bus error")
        app.rig.plug()
        app.eventually(lambda: bus_state(app) == "connected", what="reconnection")
        app.eventually(lambda: get(app, "/api/nodes/2/sdo/1008/0")[0] == 200, what="read")
        names_read(app)


def test_bus_off_while_a_write_is_sent(tmp_path: Path) -> None:
    """Expected: the controller goes bus-off exactly when the tool sends a write to node 3
    (send raises): the write answers 503 `bus_not_connected` naming the adapter error within
    the bound, the bus state turns to "error", and after recovery the write works."""
    with faulty_app(tmp_path) as app:

        def write_to_3(msg: can.Message) -> bool:
            return msg.arbitration_id == 0x603 and msg.data[0] & 0xE0 == 0x20

        app.rig.on("tx", write_to_3, lambda msg: app.rig.unplug(), times=1)
        answer, took = app.timed("PUT", "/api/nodes/3/sdo/6081/0", json={"value": 1234})
        assert took < BOUND
        body = answer.json()
        assert (answer.status_code, body["error"]) == (503, "bus_not_connected"), body
        assert "adapter" in body["message"], body
        app.eventually(lambda: bus_state(app) == "error", what="bus error")
        app.rig.plug()
        app.eventually(lambda: bus_state(app) == "connected", what="reconnection")
        deadline = time.monotonic() + 5
        while True:
            answer = app.client.put("/api/nodes/3/sdo/6081/0", json={"value": 4321})
            if answer.status_code == 200 or time.monotonic() > deadline:
                break
            time.sleep(0.05)  # the node is found again by the scan after the reconnect
        assert (answer.status_code, answer.json()["value"]) == (200, 4321), answer.json()
