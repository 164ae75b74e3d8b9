"""Fixtures shared by every test."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from can.interfaces import virtual


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
