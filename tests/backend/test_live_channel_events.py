"""The timeline and the active faults on the live WebSocket: a page sees each event as it is
published (with the id the timeline routes show) and the fault banner changes without polling;
the Network page's `event`/`history` messages are unchanged."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from fastapi.testclient import TestClient
from starlette.testclient import WebSocketTestSession

from servodesk.models.live import ServerMessage
from tests.backend.fault_rig import faulty_app, sdo_response

SIM_INJECT = "/api/nodes/1/sdo/5FF0/0"  # the simulated drive's fault injection
MDI_ALARM = 4
EMCY = 0x080
FOLLOWING_ERROR = bytes([0x11, 0x86, 0x21, 0, 0, 0, 0, 0])  # CiA 402 8611h, 1001h 21h


class Socket:
    """Reads a socket keeping every message, so a test finds one whether it came before or
    after another (events go out before the newest states of the same moment)."""

    def __init__(self, ws: WebSocketTestSession) -> None:
        self.ws = ws
        self.seen: list[dict[str, Any]] = []

    def receive(
        self, wanted: Any, limit: int = 200, after: dict[str, Any] | None = None
    ) -> dict[str, Any]:
        """The first message not taken yet that `wanted(message)` accepts; with `after`, only
        one that came after that message."""
        start = 0 if after is None else next(i for i, m in enumerate(self.seen) if m is after) + 1
        for message in self.seen[start:]:
            if not message.get("_taken") and wanted(message):
                message["_taken"] = True
                return message
        for _ in range(limit):
            received: dict[str, Any] = self.ws.receive_json()
            ServerMessage.model_validate(received)  # every message is a typed one
            self.seen.append(received)
            if wanted(received):
                received["_taken"] = True
                return received
        raise AssertionError("no such message")


def test_messages_are_in_the_schema(client: TestClient) -> None:
    schemas = client.get("/api/openapi.json").json()["components"]["schemas"]
    mapping = schemas["ServerMessage"]["discriminator"]["mapping"]
    assert {"timeline", "fault", "event", "history"} <= set(mapping)
    assert "TimelineMessage" in schemas
    assert "FaultMessage" in schemas


def test_fault_arrives_and_clears_on_the_socket(client: TestClient) -> None:
    with client.websocket_connect("/api/ws") as raw:
        ws = Socket(raw)
        assert ws.receive(lambda _m: True)["type"] == "history"  # the Network page's list, first
        assert client.put(SIM_INJECT, json={"value": MDI_ALARM}).status_code == 200
        fault = ws.receive(lambda m: m["type"] == "fault" and m["fault"] is not None)
        assert fault["node"] == 1
        assert fault["fault"]["code"] == MDI_ALARM
        assert fault["fault"]["name_en"]  # in the manual's words
        emcy = ws.receive(lambda m: m["type"] == "timeline" and m["event"]["kind"] == "emcy")
        # the same event, under the same id, as the timeline route shows it
        stored = client.get("/api/events?kind=emcy&node=1&limit=1").json()["events"][0]
        assert emcy["event"]["id"] == stored["id"]
        assert emcy["event"]["message"] == stored["message"]

        # a page that connects now sees the banner at once
        with client.websocket_connect("/api/ws") as other:
            banner = Socket(other).receive(lambda m: m["type"] == "fault")
            assert banner["node"] == 1
            assert banner["fault"]["code"] == MDI_ALARM

        assert client.post("/api/nodes/1/faults/reset").json()["ok"]
        cleared = ws.receive(lambda m: m["type"] == "fault" and m["fault"] is None)
        assert cleared["node"] == 1
        reset = ws.receive(
            lambda m: m["type"] == "timeline" and m["event"]["kind"] == "fault-reset"
        )
        assert reset["event"]["node"] == 1


def test_timeline_ids_follow_each_other_and_network_events_still_arrive(
    client: TestClient,
) -> None:
    with client.websocket_connect("/api/ws") as raw:
        ws = Socket(raw)
        for value in (100, 200):
            assert client.put("/api/nodes/2/sdo/6065/0", json={"value": value}).status_code == 200
        first = ws.receive(lambda m: m["type"] == "timeline" and m["event"]["kind"] == "tool-write")
        second = ws.receive(lambda m: m["type"] == "timeline")
        assert second["event"]["id"] == first["event"]["id"] + 1  # no gap: nothing was missed
        assert [first["event"]["data"]["value"], second["event"]["data"]["value"]] == [100, 200]
        assert client.post("/api/nodes/2/nmt", json={"command": "start"}).status_code == 200
        network = ws.receive(lambda m: m["type"] == "event")  # the Network page's message
        assert network["event"]["kind"] == "nmt"
        nmt = ws.receive(lambda m: m["type"] == "timeline" and m["event"]["kind"] == "nmt")
        assert nmt["event"]["data"] == {"tool": True, "command": "start", "broadcast": False}


def test_a_fault_message_follows_the_history_even_when_the_fault_is_gone(
    tmp_path: Path,
) -> None:
    """The Faults page reads the history when a `fault` message says it changed (it does not
    poll). An EMCY is stored only after its 6041h read: when an error-reset EMCY clears it
    before that answer, a `fault` message (still none active) follows the store all the same."""
    with faulty_app(tmp_path, sdo_timeout=1.0) as app:
        app.eventually(lambda: app.services.registry.known(3), what="node 3 identified")
        with app.client.websocket_connect("/api/ws") as raw:
            ws = Socket(raw)
            app.rig.drop("rx", sdo_response(3))  # the 6041h read after the EMCY times out
            app.inject(EMCY + 3, FOLLOWING_ERROR)
            ws.receive(lambda m: m["type"] == "fault" and m["node"] == 3 and m["fault"] is not None)
            app.inject(EMCY + 3, bytes(8))  # error reset, before the state is read
            cleared = ws.receive(
                lambda m: m["type"] == "fault" and m["node"] == 3 and m["fault"] is None
            )
            assert app.client.get("/api/nodes/3/faults").json()["total"] == 0  # not stored yet

            # the message after that one (the EMCY's own, still active, came before it)
            stored = ws.receive(
                lambda m: m["type"] == "fault" and m["node"] == 3, limit=60, after=cleared
            )
            assert stored["fault"] is None  # nothing active: the message is for the history
            faults = app.client.get("/api/nodes/3/faults").json()
            assert (faults["active"], faults["total"]) == (None, 1)
            assert faults["history"][0]["code_hex"] == "0x8611"
            assert faults["history"][0]["state_after"] is None  # the read got no answer
