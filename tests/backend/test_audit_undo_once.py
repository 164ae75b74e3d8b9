"""An audit entry is undone once: of several undos of one entry sent at the same time (forced
or not), one writes the old value back; the others answer 409 already_undone naming that undo,
and nothing else is written or entered."""

from __future__ import annotations

import asyncio
from pathlib import Path

import httpx
import pytest

from tests.backend.async_app import async_client

pytestmark = pytest.mark.anyio

OBJECT = "/api/nodes/2/sdo/6083/0"  # profile acceleration, UNSIGNED32


async def newest_id(client: httpx.AsyncClient) -> int:
    entries = (await client.get("/api/audit", params={"limit": 1})).json()
    return int(entries[0]["id"])


@pytest.mark.parametrize("force", [False, True], ids=["plain", "forced"])
async def test_simultaneous_undos_of_one_entry_write_once(tmp_path: Path, force: bool) -> None:
    async with async_client(tmp_path) as client:
        for round_ in range(3):
            before = (await client.get(OBJECT)).json()["value"]
            written = await client.put(OBJECT, json={"value": 7000 + round_})
            assert written.status_code == 200, written.text
            entry = await newest_id(client)
            answers = await asyncio.gather(
                *(client.post(f"/api/audit/{entry}/undo", json={"force": force}) for _ in range(5))
            )
            done = [a for a in answers if a.status_code == 200]
            refused = [a for a in answers if a.status_code != 200]
            assert len(done) == 1, [a.text for a in answers]
            undo = done[0].json()["id"]
            for answer in refused:
                assert answer.status_code == 409
                assert answer.json()["error"] == "already_undone"
                assert f"entry {entry}" in answer.json()["message"]
                assert f"by entry {undo}" in answer.json()["message"]
            undos = (await client.get("/api/audit", params={"action": "undo"})).json()
            assert [u["id"] for u in undos if u["undo_of"] == entry] == [undo]
            assert (await client.get(OBJECT)).json()["value"] == before
            row = (await client.get("/api/audit", params={"limit": 100})).json()
            (original,) = [e for e in row if e["id"] == entry]
            assert (original["undone_by"], original["undoable"]) == (undo, False)


async def test_an_entry_undone_before_refuses_a_forced_undo_too(
    tmp_path: Path,
) -> None:
    async with async_client(tmp_path) as client:
        await client.put(OBJECT, json={"value": 7100})
        entry = await newest_id(client)
        assert (await client.post(f"/api/audit/{entry}/undo")).status_code == 200
        again = await client.post(f"/api/audit/{entry}/undo", json={"force": True})
        assert again.status_code == 409
        assert again.json()["error"] == "already_undone"
        assert "was already undone" in again.json()["message"]
