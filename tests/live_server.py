"""The real app served by uvicorn on a free loopback port in a thread (browser tests, schema
fuzzing, anything that needs real HTTP)."""

from __future__ import annotations

import socket
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pytest
import uvicorn

from servodesk.app import STATIC_DIR, create_app, server_options
from servodesk.settings import Settings


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


@contextmanager
def serve_simulated(
    data_dir: Path,
    *,
    static_dir: Path | None = STATIC_DIR,
    overrides: dict[str, Any] | None = None,
) -> Iterator[str]:
    """The app with its simulated drives (and any other `overrides` of the settings, such as
    access tokens); yields its base URL, stops it afterwards."""
    port = free_port()
    settings = Settings(simulated=True, port=port, data_dir=data_dir, **(overrides or {}))
    app = create_app(settings, static_dir=static_dir)
    config = uvicorn.Config(
        app, host="127.0.0.1", port=port, log_level="warning", **server_options(settings)
    )
    server = uvicorn.Server(config)
    thread = threading.Thread(target=server.run, name="live-server", daemon=True)
    thread.start()
    deadline = time.monotonic() + 20
    while not server.started:
        if time.monotonic() > deadline or not thread.is_alive():
            pytest.fail("the app did not start")
        time.sleep(0.05)
    try:
        yield f"http://127.0.0.1:{port}"
    finally:
        server.should_exit = True
        thread.join(timeout=20)
