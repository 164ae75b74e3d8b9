"""Faults through the live path: 5FF0h:00 injects a fault on a simulated drive, its EMCY goes
through the collector (notifier thread → event bus → fault service) and the API answers it in
the manual's words; the fault reset clears it. One app for the module keeps it fast."""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.services import Services
from servodesk.settings import Settings
from servodesk_data import load
from servodesk_sim.frames import Frame

MDI = load("mdi-s1c")
KINCO = load("kinco")
SIM_INJECT = "5FF0/0"
WAIT = 5.0  # s a condition may take before a test gives up (not a timing assertion)


@pytest.fixture(scope="module")
def app(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path_factory.mktemp("data"))
    with TestClient(create_app(settings, static_dir=None)) as client:
        yield client


def services(client: TestClient) -> Services:
    found: Services = client.app.state.services  # type: ignore[attr-defined]
    return found


def wait_active(client: TestClient, node: int) -> dict[str, Any]:
    """The node's faults once one is active (the EMCY arrives asynchronously)."""
    for _ in range(int(WAIT / 0.01)):
        body: dict[str, Any] = client.get(f"/api/nodes/{node}/faults?limit=1").json()
        if body["active"] is not None:
            return body
        time.sleep(0.01)
    raise AssertionError(f"no active fault on node {node}")


def wait_stored(client: TestClient, node: int, active: dict[str, Any]) -> dict[str, Any]:
    """The history record of the node's active fault once the 6041h read after its EMCY is in
    (the active fault shows at once; the record is stored with the state after it)."""
    for _ in range(int(WAIT / 0.01)):
        history = client.get(f"/api/nodes/{node}/faults?limit=1").json()["history"]
        if history and history[0]["time"] == active["time"]:
            record: dict[str, Any] = history[0]
            return record
        time.sleep(0.01)
    raise AssertionError(f"no stored fault with its state after on node {node}")


def inject_and_reset(client: TestClient, node: int, code: int) -> dict[str, Any]:
    """The stored record of an injected fault (before the reset: its state after is the
    fault's own), then the reset."""
    assert (
        client.put(f"/api/nodes/{node}/sdo/{SIM_INJECT}", json={"value": code}).status_code == 200
    )
    active: dict[str, Any] = wait_active(client, node)["active"]
    fault = wait_stored(client, node, active)
    assert fault["code"] == active["code"]
    reset = client.post(f"/api/nodes/{node}/faults/reset").json()
    assert reset["ok"], reset
    assert reset["state_before"] == "Fault"
    assert reset["active"] is None
    assert client.get(f"/api/nodes/{node}/faults?limit=1").json()["active"] is None
    return fault


@pytest.mark.parametrize("alarm", MDI.faults, ids=lambda e: f"alarm{e.code}")
def test_every_mdi_alarm_arrives_in_the_manuals_words(app: TestClient, alarm: Any) -> None:
    fault = inject_and_reset(app, 1, alarm.code)
    assert fault["code"] == alarm.code
    assert fault["source"] == "vendor"
    assert fault["name_en"] == alarm.name_en
    assert fault["name_zh"] == alarm.name
    assert "MDi-S1-C CANopen manual §4.1" in fault["check"]
    assert fault["state_after"] == "Fault"


@pytest.mark.parametrize("entry", KINCO.faults, ids=lambda e: f"{e.code:X}h")
def test_every_kinco_code_arrives_in_the_manuals_words(app: TestClient, entry: Any) -> None:
    fault = inject_and_reset(app, 2, entry.code)
    assert fault["code"] == entry.code & 0xFFFF  # the EMCY carries the low 16 bits
    assert fault["source"] == "vendor"
    assert entry.name_en in fault["name_en"].split(" / ")
    assert "Kinco servo CANopen manual §8" in fault["check"]


def test_active_faults_banner_and_history(app: TestClient) -> None:
    assert app.put(f"/api/nodes/3/sdo/{SIM_INJECT}", json={"value": 0x8611}).status_code == 200
    wait_active(app, 3)
    banner = app.get("/api/faults/active").json()["faults"]
    assert [f["node"] for f in banner] == [3]
    assert banner[0]["code_hex"] == "0x8611"
    history = app.get("/api/nodes/3/faults").json()
    assert history["history"][0]["name_en"] == "Following error"
    assert history["total"] >= 1
    assert app.post("/api/nodes/3/faults/reset").json()["ok"]
    assert app.get("/api/faults/active").json() == {"faults": []}


def test_reset_of_a_drive_not_in_fault_says_so(app: TestClient) -> None:
    reset = app.post("/api/nodes/3/faults/reset").json()
    assert reset["ok"] is True
    assert "not in Fault" in reset["message"]


def test_cia402_device_history_is_decoded_and_cleared_with_confirmation(app: TestClient) -> None:
    inject_and_reset(app, 3, 0x8611)
    history = app.get("/api/nodes/3/faults/device-history").json()
    assert history["count"] >= 1
    newest = history["entries"][0]
    assert newest["value_hex"] == "0x00218611"  # 1001h 21h, code 8611h (docs/simulator.md)
    assert newest["fault"]["name_en"] == "Following error"
    assert newest["fault"]["error_register"] == 0x21
    refused = app.request("DELETE", "/api/nodes/3/faults/device-history", json={})
    assert refused.status_code == 428
    assert refused.json()["error"] == "confirmation_required"
    assert app.get("/api/nodes/3/faults/device-history").json()["count"] >= 1  # nothing written
    done = app.request("DELETE", "/api/nodes/3/faults/device-history", json={"confirm": True})
    assert done.status_code == 200
    assert app.get("/api/nodes/3/faults/device-history").json()["count"] == 0


def test_a_drive_without_1003h_says_so_and_still_reads_603f(app: TestClient) -> None:
    answer = app.get("/api/nodes/1/faults/device-history")
    assert answer.status_code == 200
    history = answer.json()
    assert history["count"] == 0
    assert history["entries"] == []
    assert history["supported"] is False


def test_unknown_codes_are_decoded_by_class(app: TestClient) -> None:
    sim = services(app).bus.sim
    assert sim is not None
    sim.inject(Frame(0x083, bytes([0x01, 0x8F, 0x01, 0, 0, 0, 0, 0])))  # node 3: 8F01h
    fault = wait_active(app, 3)["active"]
    assert fault["code_hex"] == "0x8F01"
    assert fault["source"] == "unknown"
    assert "8F01" in fault["name_en"]
    sim.inject(Frame(0x083, bytes(8)))  # error reset EMCY clears it
    for _ in range(int(WAIT / 0.01)):
        if app.get("/api/nodes/3/faults?limit=1").json()["active"] is None:
            break
        time.sleep(0.01)
    assert app.get("/api/nodes/3/faults?limit=1").json()["active"] is None


def test_emcy_storm_loses_nothing(tmp_path: Path) -> None:
    """10,000 EMCYs as fast as the simulator sends them: every one is in the history and
    nothing was dropped (the latency under a paced storm is bench/emcy_storm.py's)."""
    frames = 10_000
    settings = Settings(simulated=True, data_dir=tmp_path)
    with TestClient(create_app(settings, static_dir=None)) as client:
        sim = services(client).bus.sim
        assert sim is not None
        for i in range(frames):
            sim.inject(Frame(0x081, bytes([4 if i % 2 else 1, 0])))  # MDi alarms 4 and 1
        total = 0
        for _ in range(int(60 / 0.05)):
            total = client.get("/api/nodes/1/faults?limit=1").json()["total"]
            if total >= frames:
                break
            time.sleep(0.01)
        assert total == frames
        assert services(client).events.dropped == 0
        assert services(client).storage.dropped == 0
        emcy = client.get("/api/events?kind=emcy&node=1&limit=1000").json()["events"]
        assert len(emcy) == 1000


def test_history_survives_a_restart(tmp_path: Path) -> None:
    settings = Settings(simulated=True, data_dir=tmp_path)
    with TestClient(create_app(settings, static_dir=None)) as client:
        inject_and_reset(client, 1, 4)
        first = client.get("/api/nodes/1/faults").json()
    with TestClient(create_app(settings, static_dir=None)) as client:
        # each start of the simulated drives is a bus of its own (its drives are new ones):
        # the earlier run's faults are kept, listed with every bus's
        fresh = client.get("/api/nodes/1/faults").json()
        again = client.get("/api/nodes/1/faults", params={"all_buses": True}).json()
    assert (fresh["total"], fresh["history"]) == (0, [])
    assert again["active"] is None
    assert again["total"] == first["total"] == 1
    assert again["history"][0]["name_zh"] == "位置超差"
    assert again["history"][0]["bus"] == first["history"][0]["bus"]
