"""The PDO routes against the simulated drives (the app in simulated mode): shapes and status
codes as docs/api.md promises them."""

from __future__ import annotations

import time
from typing import Any

from fastapi.testclient import TestClient

import servodesk_data
from servodesk.pdo.context import node_facts
from servodesk.pdo.service import rules_of
from servodesk_sim.frames import Frame
from tests.backend.test_api_routes import ok, services_of, wait_for
from tests.backend.test_pdo_validate import dictionary

SDO_RX = 0x600  # SDO request COB-ID base
DOWNLOAD_COMMANDS = frozenset({0x21, 0x23, 0x27, 0x2B, 0x2F})  # SDO initiate download
PDO_KEYS = {
    "kind",
    "number",
    "cob_id",
    "valid",
    "transmission_type",
    "inhibit_time_100us",
    "event_timer_ms",
    "sync_start",
    "mapping",
    "transmission",
}


def pdo_of(pdos: list[dict[str, Any]], kind: str, number: int) -> dict[str, Any]:
    return next(p for p in pdos if p["kind"] == kind and p["number"] == number)


def nmt_state(client: TestClient, node: int) -> str:
    state: str = ok(client.get(f"/api/nodes/{node}"))["nmt_state"]
    return state


class Writes:
    """SDO writes that reached the simulated drives."""

    def __init__(self, client: TestClient) -> None:
        sim = services_of(client).bus.sim
        assert sim is not None
        self.frames: list[Frame] = []
        self.remove = sim.add_tap(self._on_frame)

    def _on_frame(self, frame: Frame, origin: object | None) -> None:
        if SDO_RX < frame.can_id <= SDO_RX + 0x7F and frame.data[0] in DOWNLOAD_COMMANDS:
            self.frames.append(frame)


def test_read_shape(client: TestClient) -> None:
    pdos = ok(client.get("/api/nodes/1/pdos"))
    assert len(pdos) == 8
    tpdo1 = pdo_of(pdos, "tpdo", 1)
    assert set(tpdo1) == PDO_KEYS
    assert tpdo1["cob_id"] == 0x181
    assert tpdo1["valid"] is True
    assert tpdo1["mapping"][0] == {"index": 0x6041, "subindex": 0, "bits": 16, "name": "Statusword"}
    assert client.get("/api/nodes/42/pdos").json()["error"] == "node_not_found"


def test_recommended_apply_in_operational(client: TestClient) -> None:
    ok(client.post("/api/nodes/3/nmt", json={"command": "start"}))
    assert nmt_state(client, 3) == "operational"
    wanted = ok(client.get("/api/nodes/3/pdos/recommended", params={"modes": "pp,pv"}))["pdos"]
    check = ok(client.post("/api/nodes/3/pdos/validate", json={"pdos": wanted}))
    assert check["ok"] is True
    assert check["problems"] == []
    assert [n["node"] for n in check["bus_load"]["nodes"]] == [1, 2, 3]
    result = ok(client.put("/api/nodes/3/pdos", json={"pdos": wanted}))  # GET shape sent back
    assert [{**p, "mapping": [m["index"] for m in p["mapping"]]} for p in result] == [
        {**p, "mapping": [m["index"] for m in p["mapping"]]} for p in wanted
    ]
    assert nmt_state(client, 3) == "operational"  # taken to Pre-operational and back


def test_invalid_configuration_is_422_and_writes_nothing(client: TestClient) -> None:
    tpdo1 = pdo_of(ok(client.get("/api/nodes/1/pdos")), "tpdo", 1)
    tpdo1["mapping"] = [{"index": 0x1017, "subindex": 0, "bits": 16}] * 5  # 80 bits, unmappable
    writes = Writes(client)
    answer = client.put("/api/nodes/1/pdos", json={"pdos": [tpdo1]})
    writes.remove()
    assert answer.status_code == 422
    body = answer.json()
    assert body["error"] == "invalid_value"
    assert {"kind": "tpdo", "number": 1}.items() <= body["problems"][0].items()
    assert any("64" in p["message"] for p in body["problems"])
    # each reason names the object to change: the mapped object, or the mapping's count
    where = {(p["index"], p["subindex"]) for p in body["problems"]}
    assert where == {(0x1017, 0), (0x1A00, 0)}
    assert writes.frames == []
    strict = client.put("/api/nodes/1/pdos", json={"pdos": [{**tpdo1, "valid": "yes"}]})
    assert strict.status_code == 422
    assert strict.json()["error"] == "invalid_request"


def test_refused_step_is_409_with_the_device_unchanged(client: TestClient) -> None:
    # a dictionary that claims 1017h is mappable: the drive knows better (06040041)
    eds = servodesk_data.eds_path("mdi-s1c").read_text(encoding="utf-8")
    section = eds.index("[1017]")
    claimed = eds[:section] + eds[section:].replace("PDOMapping=0", "PDOMapping=1", 1)
    files = {"file": ("claims.eds", claimed.encode(), "application/octet-stream")}
    ok(client.post("/api/nodes/1/od", files=files))
    before = ok(client.get("/api/nodes/1/pdos"))
    tpdo1 = dict(pdo_of(before, "tpdo", 1))
    tpdo1["mapping"] = [*tpdo1["mapping"][:1], {"index": 0x1017, "subindex": 0, "bits": 16}]
    answer = client.put("/api/nodes/1/pdos", json={"pdos": [tpdo1]})
    assert answer.status_code == 409, answer.text
    body = answer.json()
    assert body["error"] == "pdo_apply_failed"
    assert body["step"] == "write 1A00h:02 = 10170010h"
    assert body["abort_code"] == "0x06040041"
    assert body["restored"] is True
    assert ok(client.get("/api/nodes/1/pdos")) == before


def test_bus_load_export_and_recommended_errors(client: TestClient) -> None:
    load = ok(client.get("/api/bus-load", params={"threshold": 50}))
    assert load["bitrate"] == 500_000
    assert load["threshold_percent"] == 50
    assert any("500 kbit/s" in note for note in load["notes"])
    assert [n["node"] for n in load["nodes"]] == [1, 2, 3]
    assert client.get("/api/bus-load", params={"threshold": 101}).status_code == 422
    dcf = client.get("/api/nodes/2/pdos/export", params={"format": "dcf"})
    assert dcf.status_code == 200
    assert "[1800sub1]" in dcf.text.replace("[1800Sub1]", "[1800sub1]")
    snippet = client.get("/api/nodes/2/pdos/export", params={"format": "python"})
    assert snippet.status_code == 200
    assert "canopen" in snippet.text
    unknown = client.get("/api/nodes/1/pdos/recommended", params={"modes": "pp,xx"})
    assert unknown.status_code == 422
    assert unknown.json()["error"] == "invalid_value"


def test_live_check(client: TestClient) -> None:
    wanted = ok(client.get("/api/nodes/1/pdos/recommended", params={"modes": "pp"}))["pdos"]
    pdo_of(wanted, "tpdo", 1)["event_timer_ms"] = 20
    ok(client.put("/api/nodes/1/pdos", json={"pdos": wanted}))
    ok(client.post("/api/nodes/1/nmt", json={"command": "start"}))
    started = ok(client.post("/api/nodes/1/pdos/live"))
    assert started["active"] is True
    assert 0x181 in [p["cob_id"] for p in started["pdos"]]

    def tpdo1() -> dict[str, Any]:
        rows = ok(client.get("/api/nodes/1/pdos/live"))["pdos"]
        return next(p for p in rows if p["cob_id"] == 0x181)

    assert wait_for(lambda: tpdo1()["frames"] >= 10)
    time.sleep(0.3)
    row = tpdo1()
    assert row["kind"] == "tpdo"
    assert row["number"] == 1
    assert row["rate_hz"] > 0  # its value is load-dependent: measured, not asserted
    assert {"Statusword", "Position actual value"} <= {v["name"] for v in row["values"]}
    assert ok(client.delete("/api/nodes/1/pdos/live"))["active"] is False
    assert ok(client.get("/api/nodes/1/pdos/live")) == {
        "node": 1,
        "active": False,
        "since": None,
        "pdos": [],
        "drive_page": None,
    }


def test_dcf_load_handles_pdos_in_operational(client: TestClient) -> None:
    saved = client.get("/api/nodes/3/dcf").text
    before = ok(client.get("/api/nodes/3/pdos"))
    changed = dict(pdo_of(before, "tpdo", 1))
    changed["mapping"] = changed["mapping"][:1]
    ok(client.put("/api/nodes/3/pdos", json={"pdos": [changed]}))
    ok(client.post("/api/nodes/3/nmt", json={"command": "start"}))
    files = {"file": ("node3.dcf", saved.encode(), "application/octet-stream")}
    result = ok(client.post("/api/nodes/3/dcf", files=files))
    assert result["failed"] == []
    assert result["differences"] == []
    assert ok(client.get("/api/nodes/3/pdos")) == before
    assert nmt_state(client, 3) == "operational"


def test_validation_problems_name_their_object(client: TestClient) -> None:
    tpdo1 = pdo_of(ok(client.get("/api/nodes/2/pdos")), "tpdo", 1)
    tpdo1["mapping"] = [{"index": 0x6041, "subindex": 0, "bits": 12}]  # Kinco: whole bytes
    tpdo1["transmission_type"] = 250  # reserved
    check = ok(client.post("/api/nodes/2/pdos/validate", json={"pdos": [tpdo1]}))
    assert check["ok"] is False
    rows = {(p["index"], p["subindex"]): p["message"] for p in check["problems"]}
    assert set(rows) == {(0x6041, 0), (0x1800, 2)}
    assert "reserved" in rows[(0x1800, 2)]


def test_validate_takes_threshold_and_master_cycle(client: TestClient) -> None:
    pdos = ok(client.get("/api/nodes/1/pdos"))
    check = ok(
        client.post(
            "/api/nodes/1/pdos/validate",
            params={"threshold": 1, "master_period_ms": 5},
            json={"pdos": pdos},
        )
    )
    load = check["bus_load"]
    assert (load["threshold_percent"], load["master_period_ms"]) == (1, 5)
    assert load["over_threshold"] is True
    rpdo1 = next(p for p in load["nodes"][0]["pdos"] if p["kind"] == "rpdo" and p["number"] == 1)
    assert rpdo1["frames_per_s"] == 200  # the master's event-driven RPDO every 5 ms
    assert rpdo1["basis"] == "sent by the master every 5 ms (assumed master cycle)"
    default = ok(client.post("/api/nodes/1/pdos/validate", json={"pdos": pdos}))["bus_load"]
    assert (default["threshold_percent"], default["master_period_ms"]) == (70, 10)
    bad = client.post("/api/nodes/1/pdos/validate", params={"threshold": 101}, json={"pdos": []})
    assert bad.status_code == 422


def test_bus_load_names_each_assumption_once(client: TestClient) -> None:
    load = ok(client.get("/api/bus-load", params={"master_period_ms": 20}))
    master = [note for note in load["notes"] if "master cycle" in note]
    # every simulated drive has event-driven RPDOs: one line names them all
    assert len(master) == 1
    assert master[0].endswith(": counted at the assumed 20 ms master cycle")
    assert all(f"node {n} RPDO1" in master[0] for n in (1, 2, 3))
    counted = [p for n in load["nodes"] for p in n["pdos"] if p["kind"] == "rpdo"]
    assert counted
    assert {p["frames_per_s"] for p in counted} == {50}


def test_recommended_tpdos_report_a_standing_drive(client: TestClient) -> None:
    # event-driven TPDOs with ServoDesk's 100 ms event timer: a drive that stands still
    # (nothing changes) still sends its state, so the live check shows frames and a rate
    wanted = ok(client.get("/api/nodes/1/pdos/recommended", params={"modes": "pp"}))["pdos"]
    assert pdo_of(wanted, "tpdo", 1)["event_timer_ms"] == 100
    ok(client.put("/api/nodes/1/pdos", json={"pdos": wanted}))
    ok(client.post("/api/nodes/1/nmt", json={"command": "start"}))
    started = ok(client.post("/api/nodes/1/pdos/live"))
    assert all(p["rate_hz"] is None for p in started["pdos"] if p["frames"] < 2)

    def tpdo1() -> dict[str, Any]:
        rows = ok(client.get("/api/nodes/1/pdos/live"))["pdos"]
        return next(p for p in rows if p["cob_id"] == 0x181)

    assert wait_for(lambda: tpdo1()["frames"] >= 6)
    # a rate is shown (its value depends on this machine's load: bench territory, not a test's)
    row = tpdo1()
    assert row["rate_hz"] > 0
    values = {v["name"]: v for v in row["values"]}
    statusword = values["Statusword"]
    assert statusword["value"] == 0x0250
    assert statusword["raw"] == "50 02"  # the field's bytes as they travel
    assert statusword["text"] == "Switch on disabled · voltage enabled"
    assert values["Modes of operation display"]["text"] == "No mode"
    assert values["Position actual value"]["text"] is None
    assert len(values["Position actual value"]["raw"].split()) == 4
    ok(client.delete("/api/nodes/1/pdos/live"))


def test_rules(client: TestClient) -> None:
    mdi = ok(client.get("/api/nodes/1/pdos/rules"))
    assert mdi == {
        "byte_granular": True,
        "fixed_cob_ids": 4,
        "rtr_supported": False,
        "rpdo_count": 4,
        "tpdo_count": 4,
        "procedure": mdi["procedure"],
        "needs_pre_operational": False,
    }
    assert "MDi-S1-C CANopen manual §2.5.4" in mdi["procedure"]
    kinco = ok(client.get("/api/nodes/2/pdos/rules"))
    assert (kinco["fixed_cob_ids"], kinco["needs_pre_operational"]) == (0, False)
    assert "Kinco servo CANopen manual §5.4.4" in kinco["procedure"]
    cia402 = ok(client.get("/api/nodes/3/pdos/rules"))
    assert (cia402["rpdo_count"], cia402["tpdo_count"], cia402["rtr_supported"]) == (8, 8, True)
    assert cia402["needs_pre_operational"] is True
    assert "Nanotec CANopen article" in cia402["procedure"]
    assert client.get("/api/nodes/42/pdos/rules").json()["error"] == "node_not_found"


def test_rules_of_a_generic_node_are_cia_301() -> None:
    rules = rules_of(node_facts(5, "generic-cia402", dictionary("cia402"), None))
    assert (rules.rpdo_count, rules.tpdo_count) == (8, 8)  # from its dictionary
    assert (rules.fixed_cob_ids, rules.rtr_supported, rules.needs_pre_operational) == (
        0,
        True,
        False,
    )
    assert rules.procedure.endswith("(CiA 301 §7.5.2.35–38)")


def tpdo_numbers(client: TestClient, node: int) -> list[int]:
    """The valid TPDOs of `node` the bus load counts."""
    load = ok(client.get("/api/bus-load"))
    rows = next(n for n in load["nodes"] if n["node"] == node)["pdos"]
    return [p["number"] for p in rows if p["kind"] == "tpdo"]


def test_raw_writes_to_pdo_parameters_refresh_the_bus_load(client: TestClient) -> None:
    saved = client.get("/api/nodes/1/dcf").text
    assert 1 in tpdo_numbers(client, 1)  # read and cached
    # TPDO1 invalid (COB-ID bit 31) through the plain SDO route
    ok(client.put("/api/nodes/1/sdo/1800/1", json={"value": 0x80000181}))
    assert 1 not in tpdo_numbers(client, 1)
    # the saved parameter set makes it valid again
    files = {"file": ("node1.dcf", saved.encode(), "application/octet-stream")}
    assert ok(client.post("/api/nodes/1/dcf", files=files))["failed"] == []
    assert 1 in tpdo_numbers(client, 1)
