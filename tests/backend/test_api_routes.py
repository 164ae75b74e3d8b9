"""Every route of the REST and WebSocket API against the simulated drives over a virtual bus
(the app in simulated mode, as `servodesk serve --sim` runs it)."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

from servodesk.services import Services

SHARED_EDS = Path(__file__).resolve().parents[2] / ".." / "shared" / "eds"


def services_of(client: TestClient) -> Services:
    services: Services = client.app.state.services  # type: ignore[attr-defined]
    return services


def ok(response: Any) -> Any:
    assert response.status_code == 200, response.text
    return response.json()


def wait_for(condition: Any, timeout: float = 5.0) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return True
        time.sleep(0.05)
    return bool(condition())


def test_health_bus_and_interfaces(client: TestClient) -> None:
    health = ok(client.get("/api/health"))
    assert health["status"] == "ok"
    assert health["bus"]["state"] == "connected"
    assert health["bus"]["simulated"] is True
    assert ok(client.get("/api/bus"))["rx_frames"] > 0
    names = [i["name"] for i in ok(client.get("/api/bus/interfaces"))]
    assert names[:6] == ["socketcan", "pcan", "kvaser", "slcan", "socketcand", "virtual"]


def test_nodes_scan_and_identity(client: TestClient) -> None:
    nodes = ok(client.get("/api/nodes"))
    assert [(n["node"], n["profile"]) for n in nodes] == [
        (1, "mdi-s1c"),
        (2, "kinco"),
        (3, "cia402"),
    ]
    assert nodes[0]["name"] == "DVS_CANOPEN"
    scan = ok(client.post("/api/scan", json={"sdo_sweep": True, "timeout_ms": 50}))
    assert [n["node"] for n in scan["nodes"]] == [1, 2, 3]
    assert ok(client.get("/api/nodes/2"))["vendor_id"] == nodes[1]["vendor_id"]
    missing = client.get("/api/nodes/42")
    assert missing.status_code == 404
    assert missing.json()["error"] == "node_not_found"


def test_sdo_read_write_and_abort(client: TestClient) -> None:
    name = ok(client.get("/api/nodes/1/sdo/1008/0"))
    assert name["value"] == "DVS_CANOPEN"
    assert name["raw_hex"].startswith("44 56 53")
    written = ok(client.put("/api/nodes/1/sdo/607A/0", json={"value": "-1000"}))
    assert written["value"] == -1000
    assert ok(client.put("/api/nodes/1/sdo/6081/0", json={"value": "0x2710"}))["value"] == 10000
    abort = client.put("/api/nodes/1/sdo/6041/0", json={"value": 6})
    assert abort.status_code == 409
    assert abort.json() == {
        "error": "sdo_abort",
        "message": "Attempt to write a read-only object",
        "abort_code": "0x06010002",
        "node": 1,
        "index": 0x6041,
        "subindex": 0,
    }
    assert client.get("/api/nodes/1/sdo/7777/0").json()["abort_code"] == "0x06020000"
    bad = client.put("/api/nodes/1/sdo/6060/0", json={"value": 500})  # INTEGER8
    assert bad.status_code == 422
    assert bad.json()["error"] == "invalid_value"
    assert client.get("/api/nodes/1/sdo/zz/0").status_code == 422


def test_nmt_per_node_and_broadcast(client: TestClient) -> None:
    assert ok(client.post("/api/nodes/2/nmt", json={"command": "stop"}))["nmt_state"] == "stopped"
    # no SDO in Stopped (MDi-S1-C manual table 2.8): said at once, not a bare timeout
    stopped = client.get("/api/nodes/2/sdo/1000/0")
    assert stopped.status_code == 409
    assert stopped.json() == {
        "error": "node_stopped",
        "message": "node 2 is Stopped: SDO is not available in that state — set it "
        "Pre-operational or Operational",
        "node": 2,
        "message_id": "error.node_stopped",
        "params": {"node": 2},
    }
    for blocked in (
        client.get("/api/nodes/2/params"),
        client.get("/api/nodes/2/heartbeat"),
        client.put("/api/nodes/2/sdo/6060/0", json={"value": 3}),
    ):
        assert blocked.status_code == 409, blocked.text
        assert blocked.json()["error"] == "node_stopped"
    assert ok(client.post("/api/nmt", json={"command": "start"})) == {"sent": "start"}
    assert wait_for(lambda: client.get("/api/nodes/2/sdo/1000/0").status_code == 200)
    assert client.post("/api/nodes/2/nmt", json={"command": "jump"}).status_code == 422


def test_heartbeat_and_sync(client: TestClient) -> None:
    assert ok(client.put("/api/nodes/3/heartbeat", json={"producer_ms": 100})) == {
        "producer_ms": 100
    }
    assert ok(client.get("/api/nodes/3/heartbeat"))["producer_ms"] == 100
    assert wait_for(lambda: (ok(client.get("/api/nodes/3"))["heartbeat_age_ms"] or 10_000) < 300)
    assert ok(client.put("/api/sync", json={"period_us": 10_000}))["producing"] is True
    assert ok(client.get("/api/sync"))["period_us"] == 10_000
    assert ok(client.put("/api/sync", json={"period_us": 0}))["producing"] is False


def test_object_dictionary_routes(client: TestClient) -> None:
    tree = ok(client.get("/api/nodes/1/od"))
    assert tree["source"] == "profile"
    statusword = next(o for o in tree["objects"] if o["index"] == 0x6041)
    assert statusword["subs"][0]["access"] == "ro"
    kinco = SHARED_EDS / "Kinco_KINCO-JDFD.EDS"
    with kinco.open("rb") as handle:
        uploaded = ok(client.post("/api/nodes/2/od", files={"file": (kinco.name, handle)}))
    assert uploaded["source"] == "upload"
    assert ok(client.get("/api/nodes/2"))["od_source"] == "upload"
    assert ok(client.delete("/api/nodes/2/od"))["source"] == "profile"
    gbk = SHARED_EDS / "gbk_Kinco_KINCO-JDFD.eds"
    with gbk.open("rb") as handle:
        check = ok(client.post("/api/od/check", files={"file": (gbk.name, handle)}))
    assert check["objects"] > 50
    assert "encoding" in {w["code"] for w in check["warnings"]}
    junk = client.post("/api/od/check", files={"file": ("junk.eds", b"\x00\x01 not an eds")})
    assert junk.status_code == 422


def test_upload_all_job_and_cancel(client: TestClient) -> None:
    job = ok(client.post("/api/nodes/3/upload-all"))
    assert job["state"] == "running"
    assert wait_for(lambda: ok(client.get(f"/api/jobs/{job['id']}"))["state"] != "running")
    done = ok(client.get(f"/api/jobs/{job['id']}"))
    assert done["state"] == "done"
    assert done["done"] == done["total"] == len(done["results"])
    tail = ok(client.get(f"/api/jobs/{job['id']}?since={done['done'] - 1}"))
    assert tail["results_from"] == done["done"] - 1
    assert len(tail["results"]) == 1
    second = ok(client.post("/api/nodes/3/upload-all"))
    cancelled = ok(client.delete(f"/api/jobs/{second['id']}"))
    assert cancelled["state"] in {"cancelled", "done"}
    assert client.get("/api/jobs/nope").status_code == 404


def test_parameters_store_restore(client: TestClient) -> None:
    params = ok(client.get("/api/nodes/1/params"))
    assert {"PA-14", "PA-105", "PA-106"} <= {p["name"] for p in params}
    assert ok(client.get("/api/nodes/1/params/PA-14"))["value"] == 4
    result = ok(client.put("/api/nodes/1/params/PA-106", json={"value": 6}))
    assert result["requires_reset"] is True
    assert "use Change bitrate…" in result["message"]
    assert result["param"]["pending"] is True
    out_of_range = client.put("/api/nodes/1/params/PA-106", json={"value": 9})
    assert out_of_range.status_code == 422
    assert client.get("/api/nodes/1/params/PA-999").status_code == 422
    assert client.post("/api/nodes/1/store", json={}).status_code == 428
    assert "1010h" in ok(client.post("/api/nodes/1/store", json={"confirm": True}))["message"]
    assert ok(client.post("/api/nodes/1/restore-defaults", json={"confirm": True}))["message"]


def test_node_id_change_moves_the_node(client: TestClient) -> None:
    refused = client.post("/api/nodes/1/change-node-id", json={"new_node": 2, "confirm": True})
    assert refused.status_code == 422  # node 2 is taken
    moved = ok(client.post("/api/nodes/1/change-node-id", json={"new_node": 9, "confirm": True}))
    assert (moved["old_node"], moved["new_node"]) == (1, 9)
    assert moved["node"]["node"] == 9
    assert ok(client.get("/api/nodes/9/sdo/1008/0"))["value"] == "DVS_CANOPEN"
    assert client.get("/api/nodes/1").status_code == 404


def test_bitrate_change_explains_the_reconnect(client: TestClient) -> None:
    bad = client.post("/api/nodes/1/change-bitrate", json={"bitrate": 33_000, "confirm": True})
    assert bad.status_code == 422
    result = ok(
        client.post("/api/nodes/1/change-bitrate", json={"bitrate": 1_000_000, "confirm": True})
    )
    assert result["reconnect_required"] is True
    assert "1000 kbit/s" in result["steps"][-1] or "1 Mbit/s" in result["steps"][-1]


def test_dcf_save_change_compare_load(client: TestClient) -> None:
    saved = client.get("/api/nodes/3/dcf")
    assert saved.status_code == 200
    assert 'filename="node3-cia402.dcf"' in saved.headers["content-disposition"]
    dcf = saved.content
    ok(client.put("/api/nodes/3/sdo/6081/0", json={"value": 4321}))
    rows = ok(client.post("/api/nodes/3/compare", files={"file": ("n3.dcf", dcf)}))["rows"]
    changed = next(r for r in rows if (r["index"], r["subindex"]) == (0x6081, 0))
    assert changed["device"] == 4321
    assert changed["differs_from_file"] is True
    loaded = ok(client.post("/api/nodes/3/dcf", files={"file": ("n3.dcf", dcf)}))
    assert loaded["written"] > 0
    assert not [d for d in loaded["differences"] if d["index"] == 0x6081]
    assert ok(client.get("/api/nodes/3/sdo/6081/0"))["value"] != 4321
    without_file = ok(client.post("/api/nodes/3/compare"))["rows"]
    assert all(r["file"] is None for r in without_file)


def test_websocket_pushes_bus_nodes_and_node_loss(client: TestClient) -> None:
    ok(client.put("/api/nodes/3/heartbeat", json={"producer_ms": 100}))
    with client.websocket_connect("/api/ws") as ws:
        kinds: set[str] = set()
        while not {"bus", "nodes"} <= kinds:
            kinds.add(ws.receive_json()["type"])
        ws.send_json({"type": "ping"})
        sim = services_of(client).bus.sim
        assert sim is not None
        sim.stop()  # every simulated drive falls silent, as if powered off
        deadline = time.monotonic() + 10
        lost = False
        while not lost and time.monotonic() < deadline:
            message = ws.receive_json()
            lost = message["type"] == "event" and message["event"]["kind"] == "node-lost"
        assert lost
    node3 = ok(client.get("/api/nodes/3"))
    assert node3["online"] is False


def test_websocket_refuses_foreign_origin(client: TestClient) -> None:
    from starlette.websockets import WebSocketDisconnect

    with (
        pytest.raises(WebSocketDisconnect),
        client.websocket_connect("/api/ws", headers={"origin": "http://evil.example"}) as ws,
    ):
        ws.receive_json()


def test_bus_disconnect_and_reconnect(client: TestClient) -> None:
    assert ok(client.post("/api/bus/disconnect"))["state"] == "disconnected"
    gone = client.get("/api/nodes/1/sdo/1008/0")
    assert gone.status_code in {404, 503}
    assert ok(client.get("/api/nodes")) == []
    connected = ok(client.post("/api/bus/connect", json={"simulated": True}))
    assert connected["state"] == "connected"
    ok(client.post("/api/scan", json={}))
    assert ok(client.get("/api/nodes/1/sdo/1008/0"))["value"] == "DVS_CANOPEN"
    assert ok(client.post("/api/bus/reconnect"))["state"] == "connected"
    refused = client.post("/api/bus/connect", json={"interface": "nonexistent-if"})
    assert refused.status_code == 422
    assert "unknown CAN interface 'nonexistent-if'" in refused.json()["message"]
    assert ok(client.get("/api/bus"))["state"] == "connected"  # the working bus is kept
    # an adapter that does not open is refused and the bus the drives are on stays
    bad = client.post("/api/bus/connect", json={"interface": "socketcan", "channel": "nocan9"})
    assert bad.status_code == 422
    assert bad.json()["error"] == "bus_open_failed"
    assert bad.json()["message"].startswith("could not open socketcan nocan9 (")
    assert "stays connected" in bad.json()["message"]
    assert ok(client.get("/api/bus"))["state"] == "connected"
    assert ok(client.get("/api/nodes/1/sdo/1008/0"))["value"] == "DVS_CANOPEN"


def test_foreign_host_header_is_refused(client: TestClient) -> None:
    refused = client.get("/api/health", headers={"host": "evil.example"})
    assert refused.status_code == 400
    assert refused.json() == {
        "error": "bad_host",
        "message": "refused a request for host 'evil.example': ServoDesk answers only to "
        "127.0.0.1, localhost, [::1] and testserver",  # the tests' apps serve that name too
    }
    assert client.get("/api/health", headers={"host": "localhost:8000"}).status_code == 200


def test_udp_multicast_is_refused_and_not_offered(client: TestClient) -> None:
    names = {i["name"] for i in ok(client.get("/api/bus/interfaces"))}
    assert "udp_multicast" not in names
    refused = client.post("/api/bus/connect", json={"interface": "udp_multicast"})
    assert refused.status_code == 422
    assert "local network" in refused.json()["message"]
    assert ok(client.get("/api/bus"))["state"] == "connected"
