"""The parameters step and store_verify through the API on the simulated drives: a value set
through the API shows up with its audit entry; store → reset → boot-up → read-back keeps it on
a clean drive, and names it when the drive was made to lose it (5FF5h, simulator only).
Each test gets its own app: these store and reset drives."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.settings import Settings

SIM_FORGET_AT_STORE = "5FF5/0"  # simulator only: the next store does not keep this object


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path)
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


def ok(response: Any, status: int = 200) -> Any:
    assert response.status_code == status, response.text
    return response.json()


def new_record(client: TestClient, node: int) -> int:
    return int(
        ok(client.post(f"/api/nodes/{node}/commissioning", json={"modes": ["pp"]}), 201)["id"]
    )


def test_a_parameter_set_through_the_api_shows_with_its_audit_entry(client: TestClient) -> None:
    ok(client.put("/api/nodes/1/sdo/6081/0", json={"value": 4000}))  # before: not in the record
    record = new_record(client, 1)
    ok(client.put("/api/nodes/1/params/PA-103", json={"value": 5000}))
    ok(client.put("/api/nodes/1/sdo/6081/0", json={"value": 5000}))
    ok(client.put("/api/nodes/1/sdo/6081/0", json={"value": 6000}))
    ok(client.put("/api/nodes/2/sdo/6081/0", json={"value": 7000}))  # another node
    step = ok(client.post(f"/api/commissioning/{record}/steps/parameters/run"))
    assert step["status"] == "done"
    entries = step["evidence"]["entries"]
    assert [(e["object"], e["old"], e["new"]) for e in entries] == [
        ("2006:08", 6000, 5000),
        ("6081:00", 4000, 5000),
        ("6081:00", 5000, 6000),
    ]
    assert entries[0]["name"] == "PA-103"
    assert entries[0]["by"] == "local"
    audit = {e["id"]: e for e in ok(client.get("/api/audit", params={"node": 1}))}
    for entry in entries:
        logged = audit[entry["audit_id"]]
        assert (logged["index"], logged["subindex"], logged["new"]) == (
            entry["index"], entry["subindex"], entry["new"],
        )  # fmt: skip
    objects = {o["object"]: o for o in step["evidence"]["objects"]}
    assert objects["6081:00"]["old"] == 4000
    assert objects["6081:00"]["new"] == 6000
    assert objects["6081:00"]["audit_ids"] == [entries[1]["audit_id"], entries[2]["audit_id"]]


@pytest.mark.parametrize("node", [1, 2, 3])
def test_store_verify_done_on_a_clean_drive(client: TestClient, node: int) -> None:
    record = new_record(client, node)
    ok(client.put(f"/api/nodes/{node}/sdo/6081/0", json={"value": 4321}))
    step = ok(client.post(f"/api/commissioning/{record}/steps/store_verify/run"))
    assert step["status"] == "done", step["reason"]
    checked = {c["object"]: c for c in step["evidence"]["checked"]}
    assert checked["6081:00"]["expected"] == checked["6081:00"]["now"] == 4321
    assert "1017:00" in checked  # the communication values are checked too
    assert step["evidence"]["lost"] == []
    # the drive did reset: it booted again and holds the stored value
    assert ok(client.get(f"/api/nodes/{node}/sdo/6081/0"))["value"] == 4321
    assert ok(client.get(f"/api/commissioning/{record}"))["steps"][-1] == step


def test_store_verify_names_the_value_the_drive_lost(client: TestClient) -> None:
    record = new_record(client, 1)
    ok(client.put("/api/nodes/1/params/PA-103", json={"value": 5000}))  # 2006:08
    ok(client.put("/api/nodes/1/sdo/6081/0", json={"value": 4321}))
    ok(client.put(f"/api/nodes/1/sdo/{SIM_FORGET_AT_STORE}", json={"value": 0x2006_08}))
    step = ok(client.post(f"/api/commissioning/{record}/steps/store_verify/run"))
    assert step["status"] == "failed"
    assert step["evidence"]["lost"] == [
        {
            "object": "2006:08",
            "index": 0x2006,
            "subindex": 8,
            "name": "PA-103",
            "old": 6000,
            "expected": 5000,
            "now": 6000,
        }
    ]
    assert "2006:08 PA-103: expected 5000, now 6000" in step["reason"]
    # the injection object itself is not a setting of the drive: not checked
    assert "5FF5:00" not in {c["object"] for c in step["evidence"]["checked"]}
    saved = ok(client.get(f"/api/commissioning/{record}"))
    assert saved["status"] == "failed"
    assert saved["steps"][-1] == step
    # once set again and stored (the injection is used up) the step passes
    ok(client.put("/api/nodes/1/params/PA-103", json={"value": 5000}))
    again = ok(client.post(f"/api/commissioning/{record}/steps/store_verify/run"))
    assert again["status"] == "done", again["reason"]


def test_the_injection_refuses_an_object_that_is_never_stored(client: TestClient) -> None:
    refused = client.put(f"/api/nodes/1/sdo/{SIM_FORGET_AT_STORE}", json={"value": 0x5FF0_00})
    assert refused.status_code == 409
    assert refused.json()["abort_code"] == "0x06090030"


def test_a_node_that_does_not_come_back_is_a_timeout_naming_its_state(tmp_path: Path) -> None:
    # the drive is set to another bitrate: after store and reset it is silent on this bus
    settings = Settings(simulated=True, data_dir=tmp_path, boot_wait=0.5)
    with TestClient(create_app(settings, static_dir=None)) as client:
        record = new_record(client, 1)
        ok(client.put("/api/nodes/1/params/PA-106", json={"value": 6}))  # PA-106: bitrate code
        late = client.post(f"/api/commissioning/{record}/steps/store_verify/run")
        assert late.status_code == 504, late.text
        body = late.json()
        assert body["error"] == "timeout"
        assert "no boot-up within 0.5 s" in body["message"]
        assert "NMT state:" in body["message"]
        step = ok(client.get(f"/api/commissioning/{record}"))["steps"][-1]
        assert step["status"] == "failed"
        assert step["reason"] == body["message"]
