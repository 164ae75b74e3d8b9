"""A scan lists each node's hardware and firmware versions (1009h, 100Ah) where its dictionary
has them, and asks no node for objects it lacks: a scan leaves no SDO abort on the timeline."""

from __future__ import annotations

from fastapi.testclient import TestClient


def test_versions_are_read_where_the_dictionary_lists_them(client: TestClient) -> None:
    assert client.post("/api/scan", json={}).status_code == 200
    nodes = {n["node"]: n for n in client.get("/api/nodes").json()}
    assert (nodes[1]["hardware_version"], nodes[1]["software_version"]) == ("V1.0", "V1.01")
    assert (nodes[3]["hardware_version"], nodes[3]["software_version"]) == (None, None)
    events = client.get("/api/events", params={"kind": "sdo-abort"}).json()["events"]
    assert events == []
