"""What the tool writes to a drive shows on the timeline as "tool-write" events: a parameter
(old → new), store / restore, a parameter set (each entry, then the load), a PDO apply (the PDOs
changed); NMT commands keep their kind with the command named."""

from __future__ import annotations

from typing import Any

from fastapi.testclient import TestClient


def writes(client: TestClient, node: int) -> list[dict[str, Any]]:
    """The node's tool writes, oldest first."""
    page = client.get(f"/api/events?kind=tool-write&node={node}&limit=1000").json()
    return list(reversed(page["events"]))


def test_parameter_write_shows_old_and_new(client: TestClient) -> None:
    params = client.get("/api/nodes/1/params").json()
    param = next(p for p in params if p["value"] is not None and p["max"] and p["min"] is not None)
    new = param["min"] if param["value"] != param["min"] else param["max"]
    answer = client.put(f"/api/nodes/1/params/{param['name']}", json={"value": new})
    assert answer.status_code == 200, answer.text
    last = writes(client, 1)[-1]
    assert last["data"]["action"] == "param"
    assert last["data"]["name"] == param["name"]
    assert (last["data"]["old"], last["data"]["value"]) == (param["value"], new)
    assert f"{param['value']} → {new}" in last["message"]


def test_store_and_restore_are_on_the_timeline(client: TestClient) -> None:
    for route in ("store", "restore-defaults"):
        answer = client.post(f"/api/nodes/3/{route}", json={"confirm": True})
        assert answer.status_code == 200, answer.text
    actions = [w["data"]["action"] for w in writes(client, 3)]
    assert actions[-2:] == ["store", "restore-defaults"]
    assert writes(client, 3)[-2]["data"]["index"] == 0x1010


def test_parameter_set_load_writes_each_entry_then_the_count(client: TestClient) -> None:
    dcf = client.get("/api/nodes/3/dcf").text
    loaded = client.post("/api/nodes/3/dcf", files={"file": ("node3.dcf", dcf.encode())})
    assert loaded.status_code == 200, loaded.text
    result = loaded.json()
    events = writes(client, 3)
    summary = next(e for e in reversed(events) if e["data"]["action"] == "dcf-load")
    assert summary["data"]["written"] == result["written"]
    assert summary["data"]["file"] == "node3.dcf"
    assert f"{result['written']} entries written" in summary["message"]
    entries = [e for e in events if e["data"]["action"] == "dcf-entry"]
    assert len(entries) >= result["written"] - sum(
        1 for e in events if e["data"]["action"] == "pdo-apply"
    )  # PDO entries go through the PDO apply (its own event)
    assert all(e["id"] < summary["id"] for e in entries)


def test_pdo_apply_names_the_pdos_changed(client: TestClient) -> None:
    current = client.get("/api/nodes/3/pdos").json()
    wanted = client.get("/api/nodes/3/pdos/recommended", params={"modes": "pp,pv"}).json()["pdos"]
    assert client.put("/api/nodes/3/pdos", json={"pdos": wanted}).status_code == 200
    applied = writes(client, 3)[-1]
    assert applied["data"]["action"] == "pdo-apply"
    changed = applied["data"]["pdos"]
    assert changed  # the recommended set differs from the drive's defaults
    was = {f"{p['kind'].upper()}{p['number']}": p for p in current}
    assert all(name in was for name in changed)
    assert ", ".join(changed) in applied["message"]
    # applying the same again changes nothing, and says so
    assert client.put("/api/nodes/3/pdos", json={"pdos": wanted}).status_code == 200
    again = writes(client, 3)[-1]
    assert again["data"]["pdos"] == []
    assert "nothing changed" in again["message"]


def test_nmt_commands_name_the_command(client: TestClient) -> None:
    assert client.post("/api/nmt", json={"command": "pre-operational"}).status_code == 200
    nmt = client.get("/api/events?kind=nmt&limit=1").json()["events"][0]
    assert nmt["data"] == {"tool": True, "command": "pre-operational", "broadcast": True}
