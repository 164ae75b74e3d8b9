"""Parallel writes of one object: each audit entry's old value is the value the previous write
left (read in the same step on the node's thread as the write), so the entries chain without a
gap and an undo writes back a value the drive really held."""

from __future__ import annotations

import asyncio
from pathlib import Path
from typing import Any

import pytest

from tests.backend.async_app import async_client

pytestmark = pytest.mark.anyio

OBJECT = "/api/nodes/2/sdo/6081/0"  # profile velocity, UNSIGNED32


def chain_breaks(entries: list[dict[str, Any]], start: Any) -> list[str]:
    """Where an entry's old value is not the new value of the entry before it (oldest first)."""
    breaks: list[str] = []
    previous = start
    for entry in entries:
        if entry["old"] != previous:
            breaks.append(f"entry {entry['id']}: old {entry['old']}, before it {previous}")
        previous = entry["new"]
    return breaks


async def test_parallel_writes_of_one_object_chain_old_to_new(tmp_path: Path) -> None:
    async with async_client(tmp_path) as client:
        start = (await client.get(OBJECT)).json()["value"]
        values = [5000 + i for i in range(120)]
        answers = await asyncio.gather(*(client.put(OBJECT, json={"value": v}) for v in values))
        assert [a.status_code for a in answers] == [200] * len(values)
        audit = await client.get("/api/audit", params={"node": 2, "limit": 1000})
        entries = [e for e in reversed(audit.json()) if e["index"] == 0x6081]
        held = (await client.get(OBJECT)).json()["value"]
    assert len(entries) == len(values)
    assert sorted(e["new"] for e in entries) == values
    olds = [e["old"] for e in entries]
    assert len(set(olds)) == len(olds), "two writes recorded the same old value"
    assert chain_breaks(entries, start) == []
    assert entries[-1]["new"] == held
