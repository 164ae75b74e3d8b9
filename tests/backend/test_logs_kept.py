"""Decoded logs are kept within their quota and can be listed, opened again and deleted: the
oldest go when a new decode would pass the quota (the new one says so in its summary), and at
start-up; deleting one frees its space (the uploaded file itself is never kept)."""

from __future__ import annotations

import asyncio
import os
from pathlib import Path

from fastapi.testclient import TestClient

from servodesk.logs.service import LogService
from tests.backend.test_logs_api import candump


def test_decoded_logs_are_listed_opened_again_and_deleted(
    client: TestClient, tmp_path: Path
) -> None:
    files = {"file": ("first.log", candump(tmp_path), "application/octet-stream")}
    first = client.post("/api/logs/decode", files=files).json()
    files = {"file": ("second.log", candump(tmp_path), "application/octet-stream")}
    second = client.post("/api/logs/decode", files=files).json()
    kept = client.get("/api/logs").json()
    assert [(k["id"], k["name"]) for k in kept] == [
        (second["id"], "second.log"),
        (first["id"], "first.log"),
    ]  # newest first
    assert all(k["size_bytes"] > 0 for k in kept)
    data = client.get("/api/health").json()["data"]
    assert data["logs_bytes"] == sum(k["size_bytes"] for k in kept)
    again = client.get(f"/api/logs/{first['id']}").json()
    assert (again["name"], again["summary"], again["events"]) == (
        "first.log",
        first["summary"],
        first["events"],
    )
    assert client.delete(f"/api/logs/{first['id']}").status_code == 204
    assert [k["id"] for k in client.get("/api/logs").json()] == [second["id"]]
    gone = client.get(f"/api/logs/{first['id']}/events")
    assert gone.status_code == 404
    assert gone.json()["error"] == "log_not_found"
    assert client.delete(f"/api/logs/{first['id']}").status_code == 404
    assert client.get("/api/health").json()["data"]["logs_bytes"] == kept[0]["size_bytes"]
    assert client.delete("/api/logs/..%2F..%2Fservodesk.sqlite").status_code == 404


def test_the_oldest_decoded_logs_go_beyond_the_quota(tmp_path: Path) -> None:
    async def run() -> None:
        service = LogService(tmp_path / "data", max_concurrent=1, keep_bytes=None)
        try:
            log = candump(tmp_path)
            first = await service.decode("a.log", log)
            size = (await service.kept())[0].size_bytes
            second = await service.decode("b.log", log)
            os.utime(service.store.root / f"{first.id}.sqlite", (1000.0, 1000.0))  # the oldest
            service.keep_bytes = size + size // 2  # room for one
            third = await service.decode("c.log", log)
            assert third.summary[-1].startswith("removed 2 older decoded logs (")
            assert third.summary[-1].endswith(
                f"to keep decoded logs within {(size + size // 2) / 1024:.1f} kB"
            )
            assert [k.id for k in await service.kept()] == [third.id]
            assert second.id not in {k.id for k in await service.kept()}
            # a lowered quota applies at start-up (nothing is protected then)
            service.keep_bytes = 1
            await service.open()
            assert [k.id for k in await service.kept()] == []
        finally:
            service.close()

    asyncio.run(run())
