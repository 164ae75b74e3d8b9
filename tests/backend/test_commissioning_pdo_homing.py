"""The pdo and homing steps through the API on the simulated drives: the pdo step applies the
manuals' recommended mapping for the record's modes (an engineer's write), checks each mode's
objects are mapped and listens to every TPDO for its promised rate; the homing step homes with
the method set in 6098h or the one chosen, and records the result and the home offset."""

from __future__ import annotations

import time
from collections.abc import Iterator
from typing import Any

import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.settings import Settings

SIM_NEG_LIMIT, SIM_POS_LIMIT = "5FF1/0", "5FF2/0"  # simulator only: limit switch positions
REV = 131072  # the simulated motors' increments per revolution


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    settings = Settings(
        simulated=True, data_dir=tmp_path_factory.mktemp("data"), scope_live_view=False
    )
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


def ok(response: Any, status: int = 200) -> Any:
    assert response.status_code == status, response.text
    return response.json()


def record_for(client: TestClient, node: int, modes: list[str]) -> int:
    deadline = time.monotonic() + 30
    while node not in {n["node"] for n in ok(client.get("/api/nodes"))}:
        assert time.monotonic() < deadline, f"node {node} never appeared"
        time.sleep(0.02)
    made = ok(client.post(f"/api/nodes/{node}/commissioning", json={"modes": modes}), 201)
    return int(made["id"])


def run(client: TestClient, record: int, key: str, body: dict[str, Any] | None = None) -> Any:
    return client.post(f"/api/commissioning/{record}/steps/{key}/run", json=body or {})


@pytest.mark.parametrize("node", [1, 2, 3])
def test_pdo_step_applies_the_recommendation_and_sees_every_tpdo_at_its_rate(
    client: TestClient, node: int
) -> None:
    record = record_for(client, node, ["pp", "pv"])
    step = ok(run(client, record, "pdo", {"apply": True}))
    evidence = step["evidence"]
    assert step["status"] == "done", step["reason"]
    assert evidence["applied"] is True
    coverage = {row["mode"]: row for row in evidence["coverage"]}
    assert set(coverage) == {"pp", "pv"}
    assert all(not row["missing"] for row in coverage.values())
    assert coverage["pv"]["source"]  # the manual section that lists the mode's objects
    tpdos = list(evidence["live"])
    assert tpdos, "the recommended mapping has TPDOs"
    for row in tpdos:
        assert row["ok"], row
        if row["expected_hz"] is not None:
            # the simulated drive keeps its event timer: within the step's ±20 %
            assert row["measured_hz"] >= 0.8 * row["expected_hz"], row
            assert row["frames"] >= 2
    assert evidence["audit_ids"], "the mapping's writes are in the audit log"
    # the PDO table the report prints
    mapped = " ".join(row["mapping"] for row in evidence["pdos"])
    assert "6041h:00" in mapped
    assert "6040h:00" in mapped
    drive = ok(client.get(f"/api/nodes/{node}"))
    assert drive["nmt_state"] == "operational"


def test_pdo_step_names_a_tpdo_that_waits_for_a_sync_nobody_sends(client: TestClient) -> None:
    node = 3
    record = record_for(client, node, ["pv"])
    ok(run(client, record, "pdo", {"apply": True}))
    # TPDO1 made synchronous (every SYNC) while the tool sends no SYNC; the drive takes PDO
    # changes in Pre-operational only (the step starts it again)
    ok(client.post(f"/api/nodes/{node}/nmt", json={"command": "pre-operational"}))
    cob = ok(client.get(f"/api/nodes/{node}/sdo/1800/1"))["value"]
    ok(client.put(f"/api/nodes/{node}/sdo/1800/1", json={"value": cob | 0x80000000}))
    ok(client.put(f"/api/nodes/{node}/sdo/1800/2", json={"value": 1}))
    ok(client.put(f"/api/nodes/{node}/sdo/1800/1", json={"value": cob & 0x7FF}))
    step = ok(run(client, record, "pdo"))
    assert step["status"] == "failed"
    assert "TPDO1" in step["reason"]
    assert "start SYNC" in step["reason"]
    assert step["evidence"]["applied"] is False
    # applying the recommendation again puts it right
    assert ok(run(client, record, "pdo", {"apply": True}))["status"] == "done"


def test_pdo_step_names_what_a_mode_lacks(client: TestClient) -> None:
    node = 2
    record = record_for(client, node, ["pv", "pt"])
    ok(run(client, record, "pdo", {"apply": True}))
    # the RPDO carrying the targets made invalid: pv and pt lose 60FFh / 6071h
    rpdos = ok(client.get(f"/api/nodes/{node}/pdos"))
    carrier = next(
        p for p in rpdos if p["kind"] == "rpdo" and p["valid"]
        and any(m["index"] == 0x60FF for m in p["mapping"])
    )  # fmt: skip
    index = f"{0x1400 + carrier['number'] - 1:04X}"
    ok(client.post(f"/api/nodes/{node}/nmt", json={"command": "pre-operational"}))
    cob = ok(client.get(f"/api/nodes/{node}/sdo/{index}/1"))["value"]
    ok(client.put(f"/api/nodes/{node}/sdo/{index}/1", json={"value": cob | 0x80000000}))
    step = ok(run(client, record, "pdo"))
    assert step["status"] == "failed"
    assert "60FFh:00" in step["reason"]
    assert "profile velocity" in step["reason"]


def test_homing_step_with_the_chosen_method_and_the_drive_s_own(client: TestClient) -> None:
    node = 3
    record = record_for(client, node, ["pp"])
    step = ok(run(client, record, "homing", {"method": 35}))
    assert step["status"] == "done", step["reason"]
    evidence = step["evidence"]
    assert evidence["method"] == 35
    assert evidence["method_source"] == "chosen for the step"
    assert evidence["phase"] == "attained"
    assert evidence["homed"] is True
    assert evidence["home_offset"] is not None
    assert abs(evidence["position_rev"]) < 0.01
    assert step["figures"]["homing_time_s"] >= 0
    drive = ok(client.get(f"/api/nodes/{node}/drive"))
    assert drive["state"] != "operation_enabled"
    assert ok(client.get(f"/api/nodes/{node}/drive/controller"))["holder"] is None
    # node 1 is set to 17 (negative limit switch): the switch brought close
    record = record_for(client, 1, ["pp"])
    ok(client.put(f"/api/nodes/1/sdo/{SIM_NEG_LIMIT}", json={"value": -REV // 4}))
    ok(client.put(f"/api/nodes/1/sdo/{SIM_POS_LIMIT}", json={"value": 2 * REV}))
    step = ok(run(client, record, "homing"))
    assert step["status"] == "done", step["reason"]
    assert step["evidence"]["method"] == 17
    assert step["evidence"]["method_source"] == "6098h as set"
    assert "Negative limit switch" in step["evidence"]["method_name"]


def test_homing_step_refuses_a_method_the_drive_lacks_in_one_line(client: TestClient) -> None:
    record = record_for(client, 3, ["pp"])
    refused = run(client, record, "homing", {"method": 1})
    assert refused.status_code == 422
    assert "17, 18, 23, 27, 35" in refused.json()["message"]
    wrong = run(client, record, "pdo", {"method": 35})
    assert wrong.status_code == 422
    assert "it takes apply" in wrong.json()["message"]
