"""A reloaded page still shows what happened (the server keeps the recent events), and a
heartbeat fast enough to flood the bus is written only when the user confirms it."""

from __future__ import annotations

from typing import Any

from fastapi.testclient import TestClient


def first_message(client: TestClient) -> dict[str, Any]:
    with client.websocket_connect("/api/ws") as socket:
        message: dict[str, Any] = socket.receive_json()
        return message


def test_a_new_page_gets_the_recent_events_first(client: TestClient) -> None:
    assert client.post("/api/nodes/2/nmt", json={"command": "stop"}).status_code == 200
    assert client.post("/api/nodes/2/nmt", json={"command": "start"}).status_code == 200
    for _ in range(2):  # a reload: the same history again, nothing lost
        history = first_message(client)
        assert history["type"] == "history"
        messages = [event["message"] for event in history["events"]]
        assert messages[0].startswith("bus connected")
        assert messages[-2:] == ["NMT stop sent to node 2", "NMT start sent to node 2"]


def heartbeat_of(client: TestClient, node: int) -> int:
    value: int = client.get(f"/api/nodes/{node}/sdo/1017/0").json()["value"]
    return value


def test_a_flooding_heartbeat_needs_confirmation(client: TestClient) -> None:
    before = heartbeat_of(client, 3)
    refused = client.put("/api/nodes/3/heartbeat", json={"producer_ms": 1})
    assert refused.status_code == 428
    assert refused.json() == {
        "error": "confirmation_required",
        "message": "a heartbeat every 1 ms puts 1000 frames/s on the bus from node 3 alone; "
        "below 10 ms needs confirm",
    }
    assert heartbeat_of(client, 3) == before  # nothing written
    confirmed = client.put("/api/nodes/3/heartbeat", json={"producer_ms": 5, "confirm": True})
    assert confirmed.json() == {"producer_ms": 5}
    assert heartbeat_of(client, 3) == 5
    for fine in (0, 10, 1000):  # off, and sensible periods, need no question
        assert client.put("/api/nodes/3/heartbeat", json={"producer_ms": fine}).status_code == 200
        assert heartbeat_of(client, 3) == fine
