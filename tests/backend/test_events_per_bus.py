"""Two servers sharing one data directory each show their own bus's timeline: every stored
event carries the bus it came from, and GET /api/events shows the connected bus's events unless
asked for every bus's (`all_buses=true`)."""

from __future__ import annotations

import asyncio
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.events.bus import EventKind, event
from servodesk.settings import Settings
from servodesk.storage import Storage


@pytest.mark.anyio
async def test_stored_events_carry_their_bus(tmp_path: Path) -> None:
    first = Storage(tmp_path, bus_of=lambda: "socketcan can0")
    second = Storage(tmp_path, bus_of=lambda: "socketcan can1")
    await first.start()
    await second.start()
    first.add_event(event(EventKind.BUS, None, "can0 connected"))
    await first.flush()
    second.add_event(event(EventKind.BUS, None, "can1 connected"))
    await second.flush()
    assert [e.message for e in await first.events(bus="socketcan can0")] == ["can0 connected"]
    assert [(e.message, e.bus) for e in await first.events()] == [
        ("can1 connected", "socketcan can1"),
        ("can0 connected", "socketcan can0"),
    ]
    await first.close()
    await second.close()


def test_the_timeline_shows_this_servers_bus_unless_asked(tmp_path: Path) -> None:
    async def other_server() -> None:  # another server on this data directory, another bus
        storage = Storage(tmp_path, bus_of=lambda: "socketcan can7")
        await storage.start()
        storage.add_event(event(EventKind.BUS, None, "bus connected (socketcan can7)"))
        await storage.close()

    asyncio.run(other_server())
    settings = Settings(simulated=True, data_dir=tmp_path)
    with TestClient(create_app(settings, static_dir=None)) as client:
        mine = client.get("/api/events").json()["events"]
        assert mine, "this server's own events (its bus connected, boot-ups)"
        bus = client.get("/api/bus").json()
        assert {e["bus"] for e in mine} == {f"{bus['interface']} {bus['channel']}"}
        assert "bus connected (socketcan can7)" not in [e["message"] for e in mine]
        every = client.get("/api/events", params={"all_buses": True}).json()["events"]
        assert "bus connected (socketcan can7)" in [e["message"] for e in every]
