"""The app in simulated mode behind an async HTTP client, for requests that really overlap
(asyncio.gather): the same app and lifespan as the test client, without its one-at-a-time
portal."""

from __future__ import annotations

from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from pathlib import Path

import httpx

from servodesk.app import create_app
from servodesk.settings import Settings


@asynccontextmanager
async def async_client(data_dir: Path) -> AsyncIterator[httpx.AsyncClient]:
    app = create_app(Settings(simulated=True, data_dir=data_dir), static_dir=None)
    async with app.router.lifespan_context(app):
        transport = httpx.ASGITransport(app=app)
        async with httpx.AsyncClient(transport=transport, base_url="http://testserver") as client:
            yield client
