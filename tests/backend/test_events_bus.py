"""The event bus, the storage and the events route: hand-over from another thread, drops
counted and published, registry events and tool writes on the timeline, paging and filters."""

from __future__ import annotations

import asyncio
import sqlite3
import threading
import time
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from servodesk.events import BusEvent, EventBus, EventKind, event
from servodesk.storage import LATEST, Retention, Storage, migrate
from servodesk.storage.migrations import MIGRATIONS


@pytest.mark.anyio
async def test_hand_over_from_a_thread_runs_on_the_loop_and_counts_drops() -> None:
    bus = EventBus(queue_limit=10)
    bus.attach_loop()
    seen: list[BusEvent] = []
    bus.subscribe(seen.append)
    loop_thread = threading.get_ident()
    ran_on: list[int] = []

    def on_loop(i: int) -> None:
        ran_on.append(threading.get_ident())
        bus.publish(event(EventKind.EMCY, 1, f"emcy {i}"))

    def flood() -> None:
        for i in range(25):
            bus.hand_over(on_loop, i)

    thread = threading.Thread(target=flood)
    thread.start()
    thread.join()  # joined on the loop on purpose: nothing drains meanwhile, the queue fills
    for _ in range(100):
        await asyncio.sleep(0)
    assert set(ran_on) == {loop_thread}
    assert bus.dropped == 15
    kinds = [e.kind for e in seen]
    assert kinds.count(EventKind.EMCY) == 10
    dropped = [e for e in seen if e.kind is EventKind.DROPPED]
    assert len(dropped) == 1
    assert dropped[0].data == {"count": 15, "total": 15}


@pytest.mark.anyio
async def test_storage_migrates_once_and_prunes_to_its_retention(tmp_path: Path) -> None:
    store = Storage(tmp_path, Retention(max_events=10, max_days=30, max_faults=5))
    await store.start()
    for i in range(30):
        store.add_event(event(EventKind.NMT, 1, f"n{i}"))
    old = event(EventKind.BUS, None, "ancient")
    store.add_event(BusEvent(time.time() - 40 * 86400, old.kind, None, old.message, {}))
    await store.flush()
    rows = await store.events(limit=100)
    # the 10 newest ids are kept, then the one older than 30 days goes
    assert [r.message for r in rows] == [f"n{i}" for i in range(29, 20, -1)]
    await store.close()
    with sqlite3.connect(tmp_path / "servodesk.sqlite") as db:
        assert migrate(db) == LATEST  # already there: nothing runs again
        versions = db.execute("SELECT version FROM schema_version").fetchall()
        assert versions == [(v,) for v, _ in MIGRATIONS]  # each ran once, in order
        assert db.execute("PRAGMA journal_mode").fetchone() == ("wal",)


def test_timeline_paging_and_filters(client: TestClient) -> None:
    for value in (100, 200, 300):
        assert client.put("/api/nodes/3/heartbeat", json={"producer_ms": 0}).status_code == 200
        assert client.put("/api/nodes/2/sdo/6065/0", json={"value": value}).status_code == 200
    page = client.get("/api/events?limit=2").json()
    assert len(page["events"]) == 2
    assert page["events"][0]["id"] > page["events"][1]["id"]  # newest first
    older = client.get(f"/api/events?limit=2&before={page['next']}").json()
    assert older["events"][0]["id"] < page["events"][1]["id"]
    writes = client.get("/api/events?kind=tool-write&node=2").json()["events"]
    assert [w["data"]["value"] for w in writes] == [300, 200, 100]
    assert all(w["message"].startswith("wrote 6065h:00h") for w in writes)
    boots = client.get("/api/events?kind=bus").json()["events"]
    assert boots
    assert boots[-1]["message"].startswith("bus connected")
    # polling from a cursor: oldest first, and the cursor stays when nothing is new
    first = client.get("/api/events?since=0&limit=1000").json()
    ids = [e["id"] for e in first["events"]]
    assert ids == sorted(ids)
    assert client.get(f"/api/events?since={first['next']}").json() == {
        "events": [],
        "next": first["next"],
    }


def test_sdo_aborts_seen_on_the_bus_are_events(client: TestClient) -> None:
    assert client.put("/api/nodes/1/sdo/1000/0", json={"value": 1}).status_code == 409
    aborts = client.get("/api/events?kind=sdo-abort&node=1").json()["events"]
    assert aborts[0]["data"]["abort_code"] == "0x06010002"
    failed = client.get("/api/events?kind=tool-write&node=1").json()["events"]
    assert "failed" in failed[0]["message"]
