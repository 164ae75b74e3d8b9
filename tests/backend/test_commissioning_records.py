"""Commissioning records through the API on the three simulated drives: making a record
(steps the drive cannot do skipped with the reason), the read-only automated steps with their
evidence, sign-off, and the 404/409/422 answers. One app for the module: nothing here writes
to a drive."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient
from pydantic import SecretStr

from servodesk.access.actor import Role
from servodesk.access.policy import required_role
from servodesk.app import create_app
from servodesk.commissioning.plan import plan_steps
from servodesk.models.commissioning import STEP_KEYS
from servodesk.settings import Settings

DRIVES = [(1, "mdi-s1c"), (2, "kinco"), (3, "cia402")]


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path_factory.mktemp("data"))
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


def ok(response: Any, status: int = 200) -> Any:
    assert response.status_code == status, response.text
    return response.json()


def step(record: dict[str, Any], key: str) -> dict[str, Any]:
    return next(s for s in record["steps"] if s["key"] == key)


def values(evidence: dict[str, Any]) -> dict[str, Any]:
    return {v["object"]: v["value"] for v in evidence["values"]}


@pytest.mark.parametrize(("node", "profile"), DRIVES)
def test_create_on_each_drive(client: TestClient, node: int, profile: str) -> None:
    record = ok(
        client.post(f"/api/nodes/{node}/commissioning", json={"modes": ["pp", "pv", "csp"]}), 201
    )
    assert record["node"] == node
    assert record["identity"]["profile"] == profile
    assert [s["key"] for s in record["steps"]] == list(STEP_KEYS)
    assert record["status"] == "in_progress"
    assert record["modes"] == ["pp", "pv", "csp"]
    # the simulated drives announce pp, pv, pt, hm, ip in 6502h: csp is named as not supported
    assert set(record["identity"]["supported_modes"]) == {"pp", "pv", "pt", "hm", "ip"}
    assert "csp" in step(record, "test_move")["evidence"]["not_supported"]
    assert step(record, "homing")["status"] == "to_do"
    assert ok(client.get(f"/api/commissioning/{record['id']}")) == record
    listed = ok(client.get("/api/commissioning", params={"node": node}))
    assert record["id"] in [r["id"] for r in listed]
    assert all(r["node"] == node for r in listed)


def test_a_step_the_drive_cannot_do_is_skipped_with_the_reason(client: TestClient) -> None:
    record = ok(client.post("/api/nodes/2/commissioning", json={"modes": ["csp"]}), 201)
    move = step(record, "test_move")
    assert move["status"] == "skipped"
    assert move["by"] == "servodesk"
    assert "csp" in move["reason"]
    assert "6502h" in move["reason"]
    # a drive without homing (6502h without mode 6) or without PT: the plan says so
    steps = {s.key: s for s in plan_steps(frozenset({"pp", "pv"}), ["pp", "pt"])}
    assert steps["homing"].status == "skipped"
    assert "homing" in (steps["homing"].reason or "")
    assert steps["test_move"].status == "to_do"
    assert "pt" in steps["test_move"].evidence["not_supported"]
    no_speed = {s.key: s for s in plan_steps(frozenset({"pt"}), ["pt"])}
    assert no_speed["stop_test"].status == "skipped"
    unknown = {s.key: s.status for s in plan_steps(None, ["pp"])}
    assert set(unknown.values()) == {"to_do"}  # modes unknown: nothing skipped for them


@pytest.mark.parametrize(("node", "profile"), DRIVES)
def test_read_steps_record_their_evidence(client: TestClient, node: int, profile: str) -> None:
    record = ok(client.post(f"/api/nodes/{node}/commissioning", json={"modes": ["pp"]}), 201)
    base = f"/api/commissioning/{record['id']}/steps"
    identity = ok(client.post(f"{base}/identity/run"))
    assert identity["status"] == "done"
    assert identity["by"] == "local"
    assert identity["at"]
    read = values(identity["evidence"])
    assert read["1018:01"] == record["identity"]["vendor_id"]
    assert read.get("100A:00") == record["identity"]["software_version"]  # Kinco: no 100Ah
    assert identity["evidence"]["profile"] == profile
    assert identity["evidence"]["eds"]["source"] == "profile"

    comm = ok(client.post(f"{base}/communication/run"))
    assert comm["status"] == "done"
    assert comm["evidence"]["node_id"] == node
    assert "1017:00" in values(comm["evidence"])
    assert comm["evidence"]["watching_tool"] in (True, False)

    limits = ok(client.post(f"{base}/limits/run"))
    assert limits["status"] == "done"
    assert {"6085:00", "605A:00"} <= set(values(limits["evidence"]))

    again = ok(client.get(f"/api/commissioning/{record['id']}"))
    assert step(again, "identity") == identity
    assert step(again, "limits") == limits


def test_sign_off_and_skip_needs_a_reason(client: TestClient) -> None:
    record = ok(client.post("/api/nodes/3/commissioning", json={"modes": ["pp"]}), 201)
    base = f"/api/commissioning/{record['id']}/steps"
    done = ok(client.put(f"{base}/pdo", json={"status": "done"}))
    assert done["status"] == "done"
    assert done["by"] == "local"
    assert done["at"]
    refused = client.put(f"{base}/homing", json={"status": "skipped"})
    assert refused.status_code == 422
    assert refused.json()["error"] == "invalid_value"
    assert "reason" in refused.json()["message"]
    blank = client.put(f"{base}/homing", json={"status": "skipped", "reason": "  "})
    assert blank.status_code == 422
    skipped = ok(client.put(f"{base}/homing", json={"status": "skipped", "reason": "no switch"}))
    assert skipped["status"] == "skipped"
    assert skipped["reason"] == "no switch"
    # every step done or skipped: the record is done
    for key in STEP_KEYS:
        if key not in ("pdo", "homing"):
            ok(client.put(f"{base}/{key}", json={"status": "done"}))
    assert ok(client.get(f"/api/commissioning/{record['id']}"))["status"] == "done"
    # the sign-offs are audited like the app's other writes
    entries = ok(client.get("/api/audit", params={"limit": 50}))
    assert any(f"/api/commissioning/{record['id']}/steps/homing" in e["what"] for e in entries)


def test_errors(client: TestClient) -> None:
    missing = client.get("/api/commissioning/999999")
    assert missing.status_code == 404
    assert missing.json()["error"] == "commissioning_not_found"
    record = ok(client.post("/api/nodes/1/commissioning", json={"modes": ["pp"]}), 201)
    base = f"/api/commissioning/{record['id']}/steps"
    unknown_step = client.post(f"{base}/calibrate/run")
    assert unknown_step.status_code == 404
    assert unknown_step.json()["error"] == "step_not_found"
    assert client.post("/api/commissioning/999999/steps/identity/run").status_code == 404
    bad_mode = client.post("/api/nodes/1/commissioning", json={"modes": ["warp"]})
    assert bad_mode.status_code == 422
    assert "warp" in bad_mode.json()["message"]
    bad_status = client.put(f"{base}/pdo", json={"status": "failed"})
    assert bad_status.status_code == 422
    assert bad_status.json()["error"] == "invalid_request"
    no_node = client.post("/api/nodes/42/commissioning", json={"modes": ["pp"]})
    assert no_node.status_code == 404
    assert no_node.json()["error"] == "node_not_found"


def test_check_and_report_are_not_record_ids(client: TestClient) -> None:
    """/commissioning/check takes a POST only: a GET is 405, not a 422 about a record id."""
    assert client.get("/api/commissioning/check").status_code == 405
    assert client.get("/api/commissioning/999999").json()["error"] == "commissioning_not_found"


def test_roles(tmp_path: Path) -> None:
    """An operator makes a record, runs the reading steps and signs off; store_verify and
    applying a PDO mapping write to the drive, so they are the engineer's."""
    tokens = "engineer=eng-secret-0123456789,operator=op-secret-0123456789"
    settings = Settings(simulated=True, data_dir=tmp_path, tokens=SecretStr(tokens))
    operator = {"authorization": "Bearer op-secret-0123456789"}
    with TestClient(create_app(settings, static_dir=None)) as app:
        record = ok(
            app.post("/api/nodes/3/commissioning", json={"modes": ["pp"]}, headers=operator), 201
        )
        base = f"/api/commissioning/{record['id']}/steps"
        ran = ok(app.post(f"{base}/limits/run", headers=operator))
        assert ran["by"] == "operator"
        ok(app.put(f"{base}/pdo", json={"status": "done"}, headers=operator))
        refused = app.post(f"{base}/store_verify/run", headers=operator)
        assert refused.status_code == 403
        assert refused.json()["required"] == "engineer"
        # the pdo step checks for an operator; applying a mapping writes: the engineer's
        refused = app.post(f"{base}/pdo/run", json={"apply": True}, headers=operator)
        assert refused.status_code == 403
        assert refused.json()["required"] == "engineer"
        assert "without apply" in refused.json()["message"]
        assert ok(app.post(f"{base}/pdo/run", json={}, headers=operator))["by"] == "operator"
    assert required_role("POST", "/api/nodes/1/commissioning") is Role.OPERATOR
    assert required_role("POST", "/api/commissioning/4/steps/identity/run") is Role.OPERATOR
    assert required_role("PUT", "/api/commissioning/4/steps/pdo") is Role.OPERATOR
    assert required_role("POST", "/api/commissioning/4/steps/store_verify/run") is Role.ENGINEER
    assert required_role("GET", "/api/commissioning") is Role.VIEWER


def test_a_record_survives_a_restart(tmp_path: Path) -> None:
    settings = Settings(simulated=True, data_dir=tmp_path)
    with TestClient(create_app(settings, static_dir=None)) as first:
        record = ok(first.post("/api/nodes/2/commissioning", json={"modes": ["pv"]}), 201)
        ok(first.post(f"/api/commissioning/{record['id']}/steps/identity/run"))
        ok(first.put(f"/api/commissioning/{record['id']}/steps/pdo", json={"status": "done"}))
        kept = ok(first.get(f"/api/commissioning/{record['id']}"))
    with TestClient(create_app(settings, static_dir=None)) as second:
        assert ok(second.get(f"/api/commissioning/{record['id']}")) == kept
        assert [r["id"] for r in ok(second.get("/api/commissioning"))] == [record["id"]]
        # a new record after the restart gets a new id
        later = ok(second.post("/api/nodes/2/commissioning", json={"modes": ["pv"]}), 201)
        assert later["id"] > record["id"]
