"""Fixtures shared by every test."""

from __future__ import annotations

import os
from collections.abc import Iterator

import pytest
from can.interfaces import virtual

# A drive this tool controls watches its heartbeat (1016h, 300 ms by default). On a small,
# shared CI host the server's event loop can miss that by a few hundred milliseconds, and the
# held drive then faults (8130h) in the middle of a test about something else. Tests run with
# 1 s unless they set their own; the 300 ms timing itself is tested with its own settings
# (test_motion_safety) and measured by bench/jog_stop.py.
os.environ.setdefault("SERVODESK_HEARTBEAT_CONSUMER_MS", "1000")


@pytest.fixture(autouse=True)
def _no_virtual_channel_left_open() -> Iterator[None]:
    """Fail a test that leaves a python-can virtual channel open (a leaked bus keeps a thread's
    queue alive and lets frames from one test reach the next)."""
    with virtual.channels_lock:
        before = set(virtual.channels)
    yield
    with virtual.channels_lock:
        leaked = set(virtual.channels) - before
    if leaked:
        pytest.fail(f"test left python-can virtual channel(s) open: {sorted(map(str, leaked))}")
