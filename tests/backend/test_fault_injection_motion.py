"""A drive's heartbeat lost while a PV jog runs through the API: the server stops the jog by
itself, says why, the timeline shows the loss, and the axis comes to a standstill."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

from tests.backend.fault_rig import FaultyApp, faulty_app, heartbeat_of

NODE = 3  # the CiA 402 drive
PAGE = {"X-Client-Id": "page-a", "X-Client-Name": "Alice"}
WIDE = 1000 * 131072  # limit switches out of the way (motor increments)


def ok(answer: Any, status: int = 200) -> Any:
    assert answer.status_code == status, answer.json()
    return answer.json()


def drive(app: FaultyApp) -> dict[str, Any]:
    state: dict[str, Any] = ok(app.client.get(f"/api/nodes/{NODE}/drive"))
    return state


def tool_stop(app: FaultyApp, node: int) -> dict[str, Any]:
    """The newest audit entry of a stop the server made by itself (user "servodesk")."""
    entries: list[dict[str, Any]] = []

    def found() -> bool:
        entries[:] = ok(
            app.client.get("/api/audit", params={"node": node, "action": "jog-stop", "limit": 5})
        )
        return any(entry["user"] == "servodesk" and entry["result"] for entry in entries)

    app.eventually(found, what="the stop's audit entry")
    entry: dict[str, Any] = next(e for e in entries if e["user"] == "servodesk")
    return entry


def test_missed_keepalives_stop_the_jog_and_the_audit_log_says_who(tmp_path: Path) -> None:
    """Expected: a PV jog started by Alice's page gets no keep-alive: after 300 ms the server
    stops it by itself; the audit log has Alice's jog start and, after it, a jog-stop entry by
    "servodesk" (not by Alice, whose request armed the timer) naming the missed keep-alive,
    with result ok; the timeline says the jog stopped and why."""
    with faulty_app(tmp_path) as app:
        client = app.client
        for sub, value in (("5FF1/0", -WIDE), ("5FF2/0", WIDE)):
            ok(client.put(f"/api/nodes/{NODE}/sdo/{sub}", json={"value": value}))
        ok(client.post(f"/api/nodes/{NODE}/drive/enable", headers=PAGE))
        body = {"mode": "pv", "velocity_rpm": 100, "keepalive_ms": 300}
        jog = ok(client.post(f"/api/nodes/{NODE}/jog", headers=PAGE, json=body))
        app.eventually(
            lambda: ok(client.get(f"/api/jog/{jog['jog_id']}"))["state"] == "stopped",
            what="the jog stopped",
        )
        stop = tool_stop(app, NODE)
        assert "keep-alive missed for 300 ms" in stop["what"], stop
        assert (stop["role"], stop["result"]) == ("engineer", "ok"), stop
        started = ok(client.get("/api/audit", params={"node": NODE, "action": "jog"}))
        assert started, "no audit entry for the jog start"
        assert started[0]["user"] == "local", started
        assert started[0]["id"] < stop["id"]
        app.eventually(lambda: drive(app)["velocity_rpm"] == 0, what="standstill")
        timeline = ok(client.get(f"/api/events?node={NODE}&kind=tool-write"))["events"]
        stops = [e for e in timeline if e["data"]["action"] == "jog-stop"]
        assert stops, timeline
        said = {e["message"] for e in stops}
        why = "(keep-alive missed for 300 ms)"
        # the timeline says "stopping" when the stop went out, "at rest" once the axis stands
        assert said == {f"node {NODE}: PV jog stopping {why}", f"node {NODE}: PV jog at rest {why}"}
        assert {e["data"]["jog_id"] for e in stops} == {jog["jog_id"]}


def test_heartbeat_lost_during_a_jog_stops_it(tmp_path: Path) -> None:
    """Expected: node 3 produces heartbeats every 100 ms and jogs at 300 rpm, kept alive by
    the page; its heartbeats stop reaching the tool: the server stops the jog with reason
    "heartbeat lost" (keep-alives then answer 409 `jog_stopped`), the timeline has a
    node-lost event for node 3, and the axis comes to a standstill (velocity 0)."""
    with faulty_app(tmp_path) as app:
        client = app.client
        ok(client.put(f"/api/nodes/{NODE}/heartbeat", json={"producer_ms": 100}))
        for sub, value in (("5FF1/0", -WIDE), ("5FF2/0", WIDE)):  # SIM limit switches
            ok(client.put(f"/api/nodes/{NODE}/sdo/{sub}", json={"value": value}))
        ok(client.post(f"/api/nodes/{NODE}/drive/enable", headers=PAGE))
        body = {"mode": "pv", "velocity_rpm": 300, "keepalive_ms": 500}
        jog = ok(client.post(f"/api/nodes/{NODE}/jog", headers=PAGE, json=body))
        keepalive = f"/api/jog/{jog['jog_id']}/keepalive"
        deadline = time.monotonic() + 5
        while drive(app)["velocity_rpm"] < 150:  # moving (kept alive meanwhile)
            assert time.monotonic() < deadline, "the drive does not jog"
            ok(client.post(keepalive))
        lost_before = len(ok(client.get(f"/api/events?node={NODE}&kind=node-lost"))["events"])

        rule = app.rig.drop("rx", heartbeat_of(NODE))
        deadline = time.monotonic() + 5
        while True:  # the page is still there: only the lost heartbeat may stop the jog
            answer = client.post(keepalive)
            if answer.status_code != 200:
                break
            assert time.monotonic() < deadline, "the jog was not stopped"
            time.sleep(0.02)
        assert rule.hits >= 1
        refused = answer.json()
        assert (answer.status_code, refused["error"]) == (409, "jog_stopped"), refused
        info = ok(client.get(f"/api/jog/{jog['jog_id']}"))
        assert info["state"] in ("stopping", "stopped")  # "stopped" once the axis is at rest
        assert info["stop_reason"] == "heartbeat lost"
        lost = ok(client.get(f"/api/events?node={NODE}&kind=node-lost"))["events"]
        assert len(lost) > lost_before
        assert "heartbeat" in lost[0]["message"], lost[0]
        app.eventually(lambda: drive(app)["velocity_rpm"] == 0, what="standstill")
        app.eventually(
            lambda: ok(client.get(f"/api/jog/{jog['jog_id']}"))["state"] == "stopped",
            what="the jog at rest",
        )
        stop = tool_stop(app, NODE)
        assert "heartbeat lost" in stop["what"], stop
        assert stop["result"] == "ok", stop

        app.rig.remove(rule)  # the heartbeats come back: the node is back, nothing restarts
        app.eventually(
            lambda: bool(ok(client.get(f"/api/events?node={NODE}&kind=node-back"))["events"]),
            what="node-back event",
        )
        assert drive(app)["velocity_rpm"] == 0
        assert ok(client.get(f"/api/jog/{jog['jog_id']}"))["state"] == "stopped"


def test_a_socket_s_quick_stop_does_not_hold_back_its_next_message(tmp_path: Path) -> None:
    """Expected: node 1 answers reads slowly (every upload 0.1 s late): a quick stop sent on
    the live channel goes out at once, and the socket answers its next message (a ping) while
    the reading of the drive after the stop is still under way, not after all ten uploads."""
    with faulty_app(tmp_path) as app:
        slow = app.rig.delay("rx", _upload_answer_of(1), 0.1)
        with app.client.websocket_connect("/api/ws") as ws:
            ws.send_json({"type": "hello", "client_id": "page-a"})
            ws.send_json({"type": "quick_stop", "node": 1})
            ws.send_json({"type": "ping"})
            while ws.receive_json()["type"] != "pong":
                pass
            assert slow.hits < 5, f"the ping waited for {slow.hits} slow reads"
        app.rig.remove(slow)
        app.eventually(
            lambda: ok(app.client.get("/api/nodes/1/drive"))["controlword"] & 0x0087 == 0x0002,
            what="the quick stop's controlword",
        )


def _upload_answer_of(node: int) -> Any:
    """An SDO upload's answer from `node` (not a download's acknowledgement)."""

    def match(msg: Any) -> bool:
        return bool(msg.arbitration_id == 0x580 + node and msg.data[0] & 0xE0 == 0x40)

    return match
