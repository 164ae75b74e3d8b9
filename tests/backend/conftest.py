"""Fixtures shared by the backend tests: asyncio for anyio, the three simulated drives."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.settings import Settings
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


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    """The app in simulated mode, as `servodesk serve --sim` runs it, behind a test client."""
    settings = Settings(simulated=True, data_dir=tmp_path)
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client
