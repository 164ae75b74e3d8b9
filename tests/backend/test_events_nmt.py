"""A node that booted before the tool connected and sends no heartbeat is asked its NMT state
(node guarding) instead of sitting in "unknown"."""

from __future__ import annotations

import time
import uuid
from collections.abc import Iterator
from pathlib import Path

import can
import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.settings import Settings
from servodesk_sim.runner import SimBus, build_drives


@pytest.fixture
def booted_before() -> Iterator[tuple[str, SimBus]]:
    channel = f"test-guard-{uuid.uuid4().hex}"
    bus = can.Bus(interface="virtual", channel=channel)
    sim = build_drives(bus, ((1, "mdi-s1c"), (2, "kinco"), (3, "cia402")))
    sim.start()  # boot-ups go out before the tool is on the channel; 1017h is 0 on all three
    try:
        yield channel, sim
    finally:
        sim.stop()
        bus.shutdown()


def test_nodes_that_booted_earlier_are_asked_their_state(
    booted_before: tuple[str, SimBus], tmp_path: Path
) -> None:
    channel, _sim = booted_before
    settings = Settings(interface="virtual", channel=channel, data_dir=tmp_path)
    with TestClient(create_app(settings, static_dir=None)) as client:
        states: list[str] = []
        for _ in range(200):  # the guarding answers arrive just after the scan
            states = [n["nmt_state"] for n in client.get("/api/nodes").json()]
            if len(states) == 3 and "unknown" not in states:
                break
            time.sleep(0.02)
        assert states == ["pre-operational"] * 3
        assert client.post("/api/nodes/2/nmt", json={"command": "start"}).status_code == 200
        assert client.get("/api/nodes").json()[1]["nmt_state"] == "operational"
