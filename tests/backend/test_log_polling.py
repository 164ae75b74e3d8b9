"""Polling in a recorded log: the same object of a node read again at a steady period (the Drive
page polls 6041h, 6061h, 6064h, 606Ch, 6077h, 60F4h at 10 Hz) is flagged `polling`, counted in
the summary and hidden on request (GET /api/logs/{id}/events?hide_polling=true); a one-off read
and a write stay."""

from __future__ import annotations

import sqlite3
from contextlib import closing
from pathlib import Path

from fastapi.testclient import TestClient

from servodesk.logs import EventKind, LogAnalysis, LogStore
from servodesk.logs.polling import PollingDetector

T0 = 1_700_000_000.0
DRIVE_PAGE = (0x6041, 0x6061, 0x6064, 0x606C, 0x6077, 0x60F4)
SECONDS = 14


def _line(time: float, can_id: int, data: str) -> str:
    return f"({time:.6f}) can0 {can_id:03X}#{data}"


def _read(time: float, index: int, value: str = "00000000") -> list[str]:
    lo, hi = f"{index & 0xFF:02X}", f"{index >> 8:02X}"
    return [
        _line(time, 0x601, f"40{lo}{hi}0000000000"),
        _line(time + 0.0005, 0x581, f"43{lo}{hi}00{value}"),
    ]


def polled_log(path: Path) -> Path:
    lines: list[str] = []
    for tick in range(SECONDS * 10):  # 10 Hz, a little jitter as a busy tool has
        start = T0 + tick / 10 + (0.004 if tick % 3 else 0.0)
        for n, index in enumerate(DRIVE_PAGE):
            lines += _read(start + n * 0.002, index)
        if tick == 50:  # the user reads the device name once and writes the mode
            lines += _read(start + 0.05, 0x1000, "92010200")
            lines += [
                _line(start + 0.06, 0x601, "2F60600001000000"),
                _line(start + 0.0605, 0x581, "6060600000000000"),
            ]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_polling_reads_are_flagged(tmp_path: Path) -> None:
    analysis = LogAnalysis(polled_log(tmp_path / "polled.log"))
    events = list(analysis.events())
    sdo = [e for e in events if e.kind == EventKind.SDO]
    polled = [e for e in sdo if e.polling]
    # every read of a series but its first two
    assert len(polled) == len(DRIVE_PAGE) * (SECONDS * 10 - 2)
    assert {e.index for e in polled} == set(DRIVE_PAGE)
    kept = [e for e in sdo if not e.polling]
    assert {(e.index, e.text.split()[3]) for e in kept} >= {(0x1000, "read"), (0x6060, "write")}
    assert not [e for e in events if e.polling and e.kind != EventKind.SDO]
    stats = analysis.stats()
    assert stats["polling_events"] == len(polled)
    assert any(
        line.startswith(f"{len(polled):,} of {stats['events']:,} events are SDO polling reads")
        for line in analysis.summary()
    )


def test_detector_rules() -> None:
    detector = PollingDetector()
    beats = [detector.read(t, 1, 0x6041, 0) for t in (0.0, 0.1, 0.2, 0.31, 0.4)]
    assert beats == [False, False, True, True, True]
    assert not detector.read(3.0, 1, 0x6041, 0)  # off the beat: a new series starts
    assert not detector.read(3.1, 1, 0x6041, 0)
    assert detector.read(3.2, 1, 0x6041, 0)
    slow = [detector.read(t, 2, 0x6041, 0) for t in (0.0, 5.0, 10.0, 15.0)]
    assert slow == [False] * 4  # every 5 s is someone reading, not a poll loop


def test_api_hides_polling(client: TestClient, tmp_path: Path) -> None:
    data = polled_log(tmp_path / "polled.log").read_bytes()
    files = {"file": ("polled.log", data, "application/octet-stream")}
    body = client.post("/api/logs/decode", files=files).json()
    log_id = body["id"]
    assert any(e["polling"] for e in body["events"])
    shown: list[dict[str, object]] = []
    since: int | None = 0
    while since is not None:
        page = client.get(
            f"/api/logs/{log_id}/events", params={"since": since, "hide_polling": True}
        ).json()
        shown += page["events"]
        since = page["next"]
    assert not [e for e in shown if e["polling"]]
    assert body["stats"]["events"] - len(shown) == body["stats"]["polling_events"]
    texts = [str(e["text"]) for e in shown]
    assert any("SDO read 1000:00" in t for t in texts)
    assert any("SDO write 6060:00" in t for t in texts)


def test_log_decoded_before_the_flag_still_pages(tmp_path: Path) -> None:
    store = LogStore(tmp_path / "data")
    result = store.decode_file(polled_log(tmp_path / "polled.log"))
    with closing(sqlite3.connect(store.root / f"{result.id}.sqlite")) as db:
        db.execute("ALTER TABLE events DROP COLUMN polling")  # as a log decoded earlier
        db.commit()
    page = store.events(result.id, 0, 50, hide_polling=True)
    assert len(page) == 50
    assert not [e for e in page if e.polling]
