"""Fixtures shared by the backend tests: asyncio for anyio, the three simulated drives."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from tests.backend.sim_nodes import SimNodes


@pytest.fixture
def anyio_backend() -> str:
    return "asyncio"


@pytest.fixture
def nodes() -> Iterator[SimNodes]:
    """The simulated drives 1 (mdi-s1c), 2 (kinco), 3 (cia402) reached the way the registry
    reaches real ones: canopen RemoteNode + NodeSession over a virtual bus."""
    with SimNodes() as access:
        yield access
