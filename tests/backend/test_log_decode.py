"""A commissioning session recorded from the simulated drives, written by python-can's own
writers (candump, ASC, BLF, TRC, MF4), decoded back: the same events from every format."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import servodesk_data
from servodesk.logs import EventKind, LogAnalysis, LogNotFoundError, LogStore
from servodesk.logs.context import DecodeContext
from servodesk.logs.decoder import LogDecoder
from servodesk.logs.events import Event
from tests.backend.log_session import Recorded, record, write_log

FORMATS = (".log", ".asc", ".blf", ".trc", ".mf4")


@pytest.fixture(scope="module")
def frames() -> list[Recorded]:
    return record()


def _decoded(path: Path, **kwargs: object) -> tuple[list[Event], LogAnalysis]:
    analysis = LogAnalysis(path, **kwargs)  # type: ignore[arg-type]
    return list(analysis.events()), analysis


def _shape(events: list[Event]) -> list[tuple[object, ...]]:
    """What must not depend on the file format (times are relative in ASC and TRC)."""
    return [(e.kind, e.node, e.index, e.subindex, e.code, e.frame) for e in events
            if e.kind != EventKind.BUS_LOAD]  # fmt: skip


def test_every_format_decodes_to_the_same_events(frames: list[Recorded], tmp_path: Path) -> None:
    shapes = {}
    for suffix in FORMATS:
        path = tmp_path / f"session{suffix}"
        write_log(frames, path)
        events, analysis = _decoded(path)
        assert analysis.stats()["frames"] == len(frames)
        shapes[suffix] = _shape(events)
    assert all(shape == shapes[".log"] for shape in shapes.values())


def test_session_events(frames: list[Recorded], tmp_path: Path) -> None:
    path = tmp_path / "session.log"
    write_log(frames, path)
    events, analysis = _decoded(path)
    kinds = [e.kind for e in events]
    assert kinds.count(EventKind.BOOT_UP) == 3
    assert kinds.count(EventKind.NMT) == 2
    emcys = [e for e in events if e.kind == EventKind.EMCY]
    assert [(e.node, e.code) for e in emcys] == [(1, 4), (2, 0x8611), (3, 0x8611), (3, 0)]
    mdi = json.loads(emcys[0].data or "")
    assert (mdi["name_zh"], mdi["source"]) == ("位置超差", "vendor")
    (abort,) = [e for e in events if e.kind == EventKind.SDO_ABORT]
    assert (abort.node, abort.index, abort.code) == (1, 0x605A, 0x06090030)
    assert "Invalid value for parameter" in abort.text
    texts = [e.text for e in events]
    assert (
        "node 1 (MDi-S1-C CAN servo) SDO read 1008:00 Manufacturer device name = DVS_CANOPEN"
        " (segmented, 11 bytes)"
    ) in texts
    assert any("SDO write 6081:00 Profile velocity = 0x000003E8 (1000) (segmented" in t
               for t in texts)  # fmt: skip
    lost = [e for e in events if e.kind == EventKind.HEARTBEAT_LOST]
    assert [e.node for e in lost] == [2]
    states = [(e.node, e.text.split(" went to ")[1]) for e in events
              if e.kind == EventKind.CIA402_STATE]  # fmt: skip
    assert states == [(3, "Switch on disabled"), (3, "Fault (from Switch on disabled)")]
    summary = analysis.summary()
    assert summary[0].startswith(f"{len(frames)} frames over ")
    assert summary[2] == "4 EMCY(s), 1 SDO abort(s), 1 heartbeat loss(es)."
    assert any("reported a fault: alarm 4 位置超差 Position deviation too large" in s
               for s in summary)  # fmt: skip
    assert any("node 2 (Kinco servo) heartbeat stopped after" in s for s in summary)
    assert [e.seq for e in events] == list(range(len(events)))


def test_pdos_decoded_with_a_dcf(frames: list[Recorded], tmp_path: Path) -> None:
    eds = servodesk_data.eds_path("cia402").read_text(encoding="utf-8")
    dcf = tmp_path / "node3.dcf"
    dcf.write_text(eds + "\n[DeviceComissioning]\nNodeID=3\nBaudrate=500\n", encoding="utf-8")
    path = tmp_path / "session.log"
    write_log(frames, path)
    events, analysis = _decoded(path, dcf=dcf)
    pdos = [e for e in events if e.kind == EventKind.PDO]
    assert pdos
    assert all(e.node == 3 for e in pdos)
    first = json.loads(pdos[0].data or "")
    assert "6041:00" in first  # TPDO1 carries the statusword in the drive's default mapping
    assert "Statusword = " in pdos[0].text
    assert analysis.stats()["bitrate"] == 500_000


def test_heartbeat_loss_and_resume_exact_frames() -> None:
    decoder = LogDecoder(DecodeContext())
    frames = [(t / 10, 0x705, b"\x05") for t in range(5)]  # 100 ms heartbeats
    frames += [(1.5, 0x080, b""), (2.0, 0x705, b"\x05")]  # a gap of 1.6 s, then back
    events = [e for e in decoder.decode(frames) if e.kind != EventKind.BUS_LOAD]
    assert [(e.kind, e.node) for e in events] == [
        (EventKind.NMT_STATE, 5), (EventKind.HEARTBEAT_LOST, 5),
        (EventKind.HEARTBEAT_RESUMED, 5),
    ]  # fmt: skip
    assert events[1].time == pytest.approx(0.5)  # when the next heartbeat was due
    assert events[2].text == "node 5 heartbeat resumed after 1600 ms"


def test_bus_load_per_second() -> None:
    decoder = LogDecoder(DecodeContext(), bitrate=125_000)
    frames = [(i / 100, 0x181, bytes(8)) for i in range(100)]  # 100 × 135 bits in second 0
    loads = [e for e in decoder.decode(frames) if e.kind == EventKind.BUS_LOAD]
    assert [(e.time, e.code) for e in loads] == [(0.0, 108)]  # 13 500 / 125 000 = 10.8 %


def test_store_pages_events(frames: list[Recorded], tmp_path: Path) -> None:
    path = tmp_path / "session.blf"
    write_log(frames, path)
    store = LogStore(tmp_path / "data")
    result = store.decode_file(path)
    assert result.stats["frames"] == len(frames)
    assert result.name == "session.blf"
    assert store.result(result.id) == result
    first = store.events(result.id, since=0, limit=10)
    rest = store.events(result.id, since=10, limit=10_000)
    assert [e.seq for e in first + rest] == list(range(result.stats["events"]))
    assert list(store.ids()) == [result.id]
    store.delete(result.id)
    with pytest.raises(LogNotFoundError):
        store.events(result.id)
    with pytest.raises(LogNotFoundError):
        store.result("../../etc/passwd")
