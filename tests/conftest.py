"""Fixtures shared by every test."""

from __future__ import annotations

import gc
import os
from collections.abc import Iterator
from pathlib import Path

import pytest
from can.interfaces import virtual

# Starlette's TestClient sends `Host: testserver`; the app answers only to the hosts it is
# served on, so the tests' apps are served on that name too (a setting, as for any name).
os.environ.setdefault("SERVODESK_ALLOWED_HOSTS", "testserver")

E2E = Path(__file__).parent / "e2e"


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """`make pytest` runs the tests that keep no real time of their own in a pool of workers and
    then, alone on the machine, the `serial` ones: every `realtime` test, then the `browser`
    tests (a page, a server and the drives' clock in three processes per test file)."""
    for item in items:
        if item.path.is_relative_to(E2E):
            item.add_marker(pytest.mark.browser)
            item.add_marker(pytest.mark.serial)
        elif item.get_closest_marker("realtime") is not None:
            item.add_marker(pytest.mark.serial)


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


@pytest.fixture(autouse=True)
def _realtime_heap(request: pytest.FixtureRequest) -> Iterator[None]:
    """A test marked `realtime` keeps millisecond time in this process (IP streams, 1 kHz scope
    captures): the heap that earlier tests left is collected and frozen first, as the app freezes
    its own after start-up (servodesk.heap), so no full collection walks it during the test and
    stops every thread for tens of milliseconds."""
    if request.node.get_closest_marker("realtime") is None:
        yield
        return
    gc.collect()
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()
