"""One SYNC rule for validate, apply and a DCF load: SYNC produced by ServoDesk or heard from
another producer counts; without either a synchronous PDO is a warning the request acknowledges
with `sync_source: "external"` (the machine's controller), not a refusal of the mapping."""

from __future__ import annotations

from typing import Any

import can
from fastapi.testclient import TestClient

from servodesk.pdo.model import MappedObject, PdoConfig
from servodesk.pdo.sync_heard import SYNC_ID, SyncHeard
from servodesk.pdo.sync_rule import SyncPresence, sync_warnings
from servodesk_sim.frames import Frame
from tests.backend.test_api_routes import ok, services_of, wait_for

IP_MODES = {"modes": "pp,pv,pt,ip"}  # the IP mapping is synchronous (every SYNC)
STATUSWORD = MappedObject(0x6041, 0, 16)  # Statusword


def unnamed(pdos: list[dict[str, Any]]) -> list[dict[str, Any]]:
    return [
        {**p, "mapping": [(m["index"], m["subindex"], m["bits"]) for m in p["mapping"]]}
        for p in pdos
    ]


def test_warning_only_for_valid_synchronous_pdos_while_no_sync() -> None:
    pdos = [
        PdoConfig("tpdo", 1, 0x181, True, 1, mapping=(STATUSWORD,)),
        PdoConfig("tpdo", 2, 0x281, False, 1),  # invalid: sends nothing
        PdoConfig("tpdo", 3, 0x381, True, 255, mapping=(STATUSWORD,)),  # on change
    ]
    quiet = SyncPresence(producing=False, heard=False)
    [warning] = sync_warnings(pdos, quiet)
    assert (warning.kind, warning.number, warning.index, warning.subindex) == ("tpdo", 1, 0x1800, 2)
    assert "no SYNC is produced or heard" in warning.message
    assert 'sync_source "external"' in warning.message
    assert sync_warnings(pdos, SyncPresence(producing=True, heard=False)) == []
    assert sync_warnings(pdos, SyncPresence(producing=False, heard=True)) == []


def test_sync_heard_counts_other_producers_only() -> None:
    now = [100.0]
    heard = SyncHeard(clock=lambda: now[0])
    assert not heard.seen().recent
    heard.on_message_received(can.Message(arbitration_id=SYNC_ID, is_extended_id=False))
    now[0] += 0.01
    heard.on_message_received(can.Message(arbitration_id=SYNC_ID, is_extended_id=False))
    # an adapter's echo of a frame sent on this side, and other ids, are not SYNC heard
    echo = can.Message(arbitration_id=SYNC_ID, is_extended_id=False, is_rx=False)
    heard.on_message_received(echo)
    heard.on_message_received(can.Message(arbitration_id=0x81, is_extended_id=False))
    seen = heard.seen()
    assert (seen.frames, seen.period_us, seen.recent) == (2, 10_000, True)
    now[0] += 5
    assert not heard.seen().recent


def test_recommended_ip_mapping_warns_and_is_written_when_acknowledged(
    client: TestClient,
) -> None:
    wanted = ok(client.get("/api/nodes/3/pdos/recommended", params=IP_MODES))["pdos"]
    check = ok(client.post("/api/nodes/3/pdos/validate", json={"pdos": wanted}))
    assert check["problems"] == []  # the manual's mapping is right for the drive
    assert check["ok"] is False  # ... but SYNC has to come from somewhere
    assert {(w["kind"], w["number"]) for w in check["warnings"]} >= {("rpdo", 1)}
    assert check["sync"] == {
        "producing": False,
        "period_us": None,
        "heard": False,
        "heard_frames": 0,
        "heard_period_us": None,
        "source": None,
    }
    refused = client.put("/api/nodes/3/pdos", json={"pdos": wanted})
    assert refused.status_code == 422
    assert 'sync_source "external"' in refused.json()["message"]

    body = {"pdos": wanted, "sync_source": "external"}
    acknowledged = ok(client.post("/api/nodes/3/pdos/validate", json=body))
    assert acknowledged["ok"] is True
    assert acknowledged["warnings"] == check["warnings"]  # still said, now acknowledged
    assert acknowledged["sync"]["source"] == "external"
    written = ok(client.put("/api/nodes/3/pdos", json=body))
    assert unnamed(written) == unnamed(wanted)
    assert unnamed(ok(client.get("/api/nodes/3/pdos"))) == unnamed(wanted)


def test_sync_heard_on_the_bus_counts_as_a_producer(client: TestClient) -> None:
    sim = services_of(client).bus.sim
    assert sim is not None
    wanted = ok(client.get("/api/nodes/3/pdos/recommended", params=IP_MODES))["pdos"]
    for _ in range(3):  # the machine's controller produces SYNC
        sim.inject(Frame(SYNC_ID, b""))
    pdos = services_of(client).pdos
    assert wait_for(lambda: pdos.sync_heard.seen().frames == 3)
    check = ok(client.post("/api/nodes/3/pdos/validate", json={"pdos": wanted}))
    assert (check["ok"], check["warnings"]) == (True, [])
    assert check["sync"]["heard"] is True
    assert check["sync"]["heard_frames"] == 3
    ok(client.put("/api/nodes/3/pdos", json={"pdos": wanted}))


def test_own_sync_is_produced_not_heard(client: TestClient) -> None:
    ok(client.put("/api/sync", json={"producing": True, "period_us": 10_000}))
    wanted = ok(client.get("/api/nodes/3/pdos/recommended", params=IP_MODES))["pdos"]
    check = ok(client.post("/api/nodes/3/pdos/validate", json={"pdos": wanted}))
    assert (check["ok"], check["warnings"]) == (True, [])
    assert (check["sync"]["producing"], check["sync"]["period_us"]) == (True, 10_000)
    assert check["sync"]["heard_frames"] == 0  # its own frames never come back as heard
    ok(client.put("/api/sync", json={"producing": False}))


def test_dcf_load_writes_synchronous_pdos_and_warns(client: TestClient) -> None:
    wanted = ok(client.get("/api/nodes/3/pdos/recommended", params=IP_MODES))["pdos"]
    ok(client.put("/api/nodes/3/pdos", json={"pdos": wanted, "sync_source": "external"}))
    saved = client.get("/api/nodes/3/dcf").text
    before = ok(client.get("/api/nodes/3/pdos"))
    plain = ok(client.get("/api/nodes/3/pdos/recommended", params={"modes": "pp"}))["pdos"]
    ok(client.put("/api/nodes/3/pdos", json={"pdos": plain}))  # event-driven: no warning
    files = {"file": ("node3.dcf", saved.encode(), "application/octet-stream")}
    result = ok(client.post("/api/nodes/3/dcf", files=files))
    assert result["failed"] == []
    assert ok(client.get("/api/nodes/3/pdos")) == before
    assert result["warnings"]
    assert all("no SYNC is produced or heard" in w for w in result["warnings"])
    assert any(w.startswith("RPDO1 is synchronous") for w in result["warnings"])


def test_recommended_leaves_unused_pdos_as_they_are(client: TestClient) -> None:
    device = ok(client.get("/api/nodes/3/pdos"))
    wanted = ok(client.get("/api/nodes/3/pdos/recommended", params=IP_MODES))["pdos"]
    now = {(p["kind"], p["number"]): p for p in device}
    used = {(p["kind"], p["number"]) for p in wanted if p["valid"]}
    valid_now = {key for key, p in now.items() if p["valid"]}
    assert len(wanted) == 16 > len(used)  # the cia402 drive has 8 + 8 PDOs
    differ = {(p["kind"], p["number"]) for p in wanted if p != now[p["kind"], p["number"]]}
    # what the mapping uses, and what it makes invalid; an invalid PDO stays as it is
    assert differ == used | valid_now
    for pdo in wanted:
        if (pdo["kind"], pdo["number"]) not in used:
            assert pdo["mapping"] == []
