"""A huge value in a request is stored shortened, with its length noted, in the audit log and
on the timeline: what a client sends cannot grow the databases by its size."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.bounded import bounded, bounded_json, shorten
from servodesk.settings import Settings

HUGE = 500_000  # characters: under the API's body limit, far over what is stored


@pytest.mark.parametrize(
    ("text", "limit", "kept"),
    [
        ("abc", 3, "abc"),
        ("abcd", 3, "abc… (4 characters)"),
        ("x" * 104_857_600, 200, "x" * 200 + "… (104857600 characters)"),
    ],
)
def test_shorten_keeps_the_start_and_notes_the_length(text: str, limit: int, kept: str) -> None:
    assert shorten(text, limit) == kept


def test_an_events_detail_is_bounded_however_it_is_nested() -> None:
    detail = {"value": "v" * 5000, "list": ["w" * 5000], "k" * 5000: 1, "n": 2}
    small = bounded(detail, 10)
    assert small["value"] == "v" * 10 + "… (5000 characters)"
    assert small["list"] == ["w" * 10 + "… (5000 characters)"]
    assert small["n"] == 2
    assert len(bounded_json({f"k{i}": "x" * 900 for i in range(100)})) < 100


def sizes(data_dir: Path) -> int:
    return sum(f.stat().st_size for f in data_dir.glob("*.sqlite*"))


def test_a_huge_value_is_stored_shortened(tmp_path: Path) -> None:
    settings = Settings(simulated=True, data_dir=tmp_path)
    with TestClient(create_app(settings, static_dir=None)) as client:
        client.put("/api/nodes/1/sdo/6081/0", json={"value": 1})
        before = sizes(tmp_path)
        for _ in range(5):
            answer = client.put("/api/nodes/1/sdo/6081/0", json={"value": "x" * HUGE})
            assert answer.status_code == 422
        entry = client.get("/api/audit", params={"limit": 1}).json()[0]
        events = client.get("/api/events", params={"node": 1}).json()["events"]
        grown = sizes(tmp_path) - before
    assert entry["result"] == "failed"
    for text in (entry["what"], entry["message"], str(entry["new"])):
        assert len(text) <= 1100, text[:80]
    assert re.search(r"… \(50\d{4} characters\)$", entry["message"]), entry["message"][-80:]
    write = next(e for e in events if e["kind"] == "tool-write" and "failed" in e["message"])
    assert len(write["message"]) <= 2200
    assert f"({HUGE} characters)" in write["message"]
    assert len(str(write["data"])) < 3000
    assert grown < 400_000, f"{grown} bytes for 5 writes"
