"""Requests that overlap a change of the node's dictionary, a bus reconnect, or each other: each
one completes, or gets a typed error in the documented shape — never a bare 500."""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from typing import Any

import httpx
import pytest
from fastapi.testclient import TestClient

from servodesk_data import eds_path

TYPED = {"interrupted", "bus_not_connected", "node_not_found", "timeout"}


def parallel_reads_during(
    client: TestClient, change: Callable[[], Any], reads: int = 40
) -> list[httpx.Response]:
    """`reads` parallel SDO reads of 1008h on node 1 with `change` made in the middle."""
    with ThreadPoolExecutor(max_workers=12) as pool:
        first = [pool.submit(client.get, "/api/nodes/1/sdo/1008/0") for _ in range(reads // 2)]
        changed = pool.submit(change)
        second = [pool.submit(client.get, "/api/nodes/1/sdo/1008/0") for _ in range(reads // 2)]
        changed.result()
        return [future.result() for future in first + second]


def assert_typed(responses: list[httpx.Response]) -> int:
    """Every answer is the value or a typed error; returns how many were values."""
    values = 0
    for response in responses:
        if response.status_code == 200:
            assert response.json()["text"] == "DVS_CANOPEN"
            values += 1
            continue
        assert response.status_code in (404, 503, 504), response.text
        body = response.json()
        assert body["error"] in TYPED
        assert body["message"]
    return values


def upload_mdi_eds(client: TestClient) -> None:
    with eds_path("mdi-s1c").open("rb") as file:
        response = client.post("/api/nodes/1/od", files={"file": ("mdi.eds", file)})
    assert response.status_code == 200, response.text


@pytest.mark.parametrize(
    "change",
    [
        pytest.param(lambda c: c.delete("/api/nodes/1/od"), id="dictionary-deleted"),
        pytest.param(upload_mdi_eds, id="dictionary-replaced"),
    ],
)
def test_reads_complete_while_the_dictionary_changes(
    client: TestClient, change: Callable[[TestClient], Any]
) -> None:
    for _ in range(3):
        responses = parallel_reads_during(client, lambda: change(client))
        # the node's session is kept: every read completes, with the old or the new dictionary
        assert assert_typed(responses) == len(responses)


def test_reads_during_a_reconnect_get_typed_errors(client: TestClient) -> None:
    responses = parallel_reads_during(client, lambda: client.post("/api/bus/reconnect"))
    assert_typed(responses)


def test_upload_all_says_why_it_stopped_when_the_dictionary_changes(client: TestClient) -> None:
    job = client.post("/api/nodes/3/upload-all").json()
    assert client.delete("/api/nodes/3/od").status_code == 200
    for _ in range(100):
        state = client.get(f"/api/jobs/{job['id']}").json()
        if state["state"] != "running":
            break
    assert state["state"] == "cancelled"
    assert state["error"] == "cancelled: the node's dictionary changed"


def test_a_write_reports_its_own_value_not_a_parallel_one(client: TestClient) -> None:
    def put(value: int) -> tuple[int, Any]:
        response = client.put("/api/nodes/1/sdo/6060/0", json={"value": value})
        assert response.status_code == 200, response.text
        return value, response.json()["value"]

    with ThreadPoolExecutor(max_workers=16) as pool:
        results = list(pool.map(put, [1, 3] * 100))
    assert [sent for sent, _ in results] == [back for _, back in results]


def test_nodes_come_back_by_themselves_after_a_reconnect(client: TestClient) -> None:
    before = [node["node"] for node in client.get("/api/nodes").json()]
    assert before == [1, 2, 3]
    for route in ("/api/bus/reconnect", "/api/bus/disconnect"):
        assert client.post(route).status_code == 200
        if route.endswith("disconnect"):
            assert client.get("/api/nodes").json() == []
            assert client.post("/api/bus/connect", json={"simulated": True}).status_code == 200
        nodes: list[int] = []
        for _ in range(100):
            nodes = [node["node"] for node in client.get("/api/nodes").json()]
            if nodes == before:
                break
            services = client.app.state.services  # type: ignore[attr-defined]
            client.portal.call(services.registry.settled)  # type: ignore[union-attr]
        assert nodes == before
        assert client.get("/api/nodes/1/sdo/1008/0").json()["text"] == "DVS_CANOPEN"
