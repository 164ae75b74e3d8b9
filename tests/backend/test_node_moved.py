"""A drive whose node id was changed outside the wizard (MDi PA-105, store, reset) leaves its
old entry behind: that entry says the drive answers at the new id now and can be forgotten, and
the wizard back to the old id asks the bus, not the list. A drive the wizard cannot re-address
says so before the first step."""

from __future__ import annotations

import time
from typing import Any

import pytest
from fastapi.testclient import TestClient

from servodesk.models.nodes import NodeInfo
from servodesk.nodes.moved import moved


def info(node: int, online: bool, serial: int | None = 77, vendor: int = 1) -> NodeInfo:
    return NodeInfo(
        node=node,
        vendor_id=vendor,
        product_code=2,
        serial=serial,
        profile="p",
        profile_label="P",
        online=online,
    )


@pytest.mark.parametrize(
    ("nodes", "expected"),
    [
        ([info(1, False), info(5, True)], {1: 5}),
        ([info(1, True), info(5, True)], {}),  # both answer: two drives, not one moved
        ([info(1, False), info(5, False)], {}),  # neither answers: nothing to point at
        ([info(1, False, serial=0), info(5, True, serial=0)], {}),  # no serial: cannot tell
        ([info(1, False), info(5, True, vendor=9)], {}),  # another vendor's device
    ],
)
def test_an_offline_entry_names_where_its_device_answers(
    nodes: list[NodeInfo], expected: dict[int, int]
) -> None:
    assert moved(nodes) == expected


def ok(response: Any) -> Any:
    assert response.status_code in (200, 204), response.text
    return response.json() if response.status_code == 200 else None


def node_list(client: TestClient) -> dict[int, dict[str, Any]]:
    return {n["node"]: n for n in ok(client.get("/api/nodes"))}


def wait_for(condition: Any, what: str, timeout: float = 10.0) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if condition():
            return
        time.sleep(0.05)
    raise AssertionError(f"{what} within {timeout} s")


def test_a_drive_readdressed_by_its_parameter_leaves_a_ghost_that_can_be_forgotten(
    client: TestClient,
) -> None:
    ok(client.post("/api/scan", json={}))
    ok(client.put("/api/nodes/1/params/PA-105", json={"value": 5}))
    ok(client.post("/api/nodes/1/store", json={"confirm": True}))
    ok(client.post("/api/nodes/1/nmt", json={"command": "reset-node"}))
    wait_for(lambda: node_list(client).get(5, {}).get("online"), "node 5 listed online")
    ok(client.post("/api/scan", json={}))  # node 1 no longer answers: listed offline
    nodes = node_list(client)
    assert (nodes[1]["online"], nodes[1]["moved_to"]) == (False, 5)
    assert nodes[5]["moved_to"] is None
    online = client.delete("/api/nodes/5")
    assert online.status_code == 409
    assert online.json()["error"] == "node_online"
    assert client.delete("/api/nodes/1").status_code == 204
    assert sorted(node_list(client)) == [2, 3, 5]
    assert client.get("/api/nodes/1").status_code == 404


def test_the_wizard_back_to_an_old_id_asks_the_bus_not_the_list(client: TestClient) -> None:
    ok(client.post("/api/scan", json={}))
    ok(client.put("/api/nodes/1/params/PA-105", json={"value": 6}))
    ok(client.post("/api/nodes/1/store", json={"confirm": True}))
    ok(client.post("/api/nodes/1/nmt", json={"command": "reset-node"}))
    wait_for(lambda: node_list(client).get(6, {}).get("online"), "node 6 listed online")
    assert 1 in node_list(client)  # the ghost is still listed
    back = client.post("/api/nodes/6/change-node-id", json={"new_node": 1, "confirm": True})
    assert back.status_code == 200, back.text  # node 1 is silent on the bus: free
    nodes = node_list(client)
    assert nodes[1]["online"]
    assert 6 not in nodes
    taken = client.post("/api/nodes/1/change-node-id", json={"new_node": 2, "confirm": True})
    assert taken.status_code == 422
    assert "node 2 is already in use on the bus" in taken.json()["message"]


def test_the_wizard_says_up_front_whether_it_can(client: TestClient) -> None:
    assert ok(client.get("/api/nodes/1/node-id-options")) == {
        "settable": True,
        "note": "Set with PA-105 (2006:0A); node ids 1..127.",
    }
    cia402 = ok(client.get("/api/nodes/3/node-id-options"))
    assert cia402["settable"] is False
    assert "has no node-id parameter ServoDesk knows" in cia402["note"]
