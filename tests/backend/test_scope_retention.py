"""Captures stay within their quota: the oldest finished ones go (never an armed or running
one, nor the capture just ended), and a recording capture ends before it passes the quota or
fills the disk; the ended capture's notes say what went and why."""

from __future__ import annotations

from pathlib import Path

from servodesk.models.scope import CaptureState
from servodesk.scope.retention import prune, pruned_note, room_left
from servodesk.scope.store import CaptureStore
from servodesk.storage.quota import MB, Kept
from tests.backend.test_scope_store_export import make_capture

KB = 1024


def stored(store: CaptureStore, states: list[CaptureState], size: int) -> list[int]:
    ids = []
    for state in states:
        capture = store.create(lambda i, s=state: make_capture(i, s))  # type: ignore[misc]
        store.samples_path(capture.id).write_bytes(b"\0" * size)
        ids.append(capture.id)
    return ids


def test_the_oldest_finished_captures_go_to_fit_the_quota(tmp_path: Path) -> None:
    store = CaptureStore(tmp_path / "scope")
    store.open()
    running, old, older_done, failed, newest = stored(
        store, ["running", "done", "done", "failed", "done"], 400 * KB
    )
    removed = prune(store, 1 * MB, protect={newest})
    # 5 × 400 kB: three must go; the running one and the protected newest stay
    assert [int(k.id) for k in removed] == [old, older_done, failed]
    assert [c.id for c in store.list()] == [newest, running]
    assert not (tmp_path / "scope" / str(old)).exists()  # its files went with it
    assert prune(store, 1 * MB) == []  # what is left fits


def test_a_note_names_what_went(tmp_path: Path) -> None:
    removed = [Kept("000000000003", 3 * MB, 1.0), Kept("000000000004", 512 * KB, 2.0)]
    assert pruned_note(removed, 8 * 1024 * MB) == (
        "removed captures 3 (3.0 MB) and 4 (512.0 kB) to keep captures within 8.0 GB"
    )
    assert pruned_note(removed[:1], 2 * MB) == (
        "removed capture 3 (3.0 MB) to keep captures within 2.0 MB"
    )


def test_a_recording_capture_ends_at_its_quota_or_a_nearly_full_disk(tmp_path: Path) -> None:
    store = CaptureStore(tmp_path / "scope")
    store.open()
    (capture,) = stored(store, ["running"], 300 * KB)
    assert room_left(store, capture, 1 * MB, min_free=0) is None
    assert room_left(store, capture, 256 * KB, min_free=0) == (
        "ended at 256.0 kB, the size kept for captures"
    )
    no_room = room_left(store, capture, 1 * MB, min_free=1 << 60)
    assert no_room is not None
    assert no_room.startswith("ended early: the disk has ")
    assert no_room.endswith(
        "free, less than the 1073741824.0 GB kept for the audit log and the timeline"
    )
