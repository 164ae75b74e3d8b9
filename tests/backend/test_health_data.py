"""GET /api/health says what the data directory holds (decoded logs, captures, recordings),
against the quotas that keep it, and how much its disk has left."""

from __future__ import annotations

import asyncio
import shutil
from pathlib import Path

from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.settings import Settings
from servodesk.storage.usage import UsageMeter

MB = 1 << 20


def test_health_reports_the_data_directory(tmp_path: Path) -> None:
    (tmp_path / "logs").mkdir()
    (tmp_path / "logs" / f"{'a' * 32}.sqlite").write_bytes(b"\0" * (3 * MB))
    (tmp_path / "recordings").mkdir()
    (tmp_path / "recordings" / "bus.blf").write_bytes(b"\0" * MB)
    settings = Settings(simulated=True, data_dir=tmp_path, logs_keep_mb=100, captures_keep_mb=7)
    with TestClient(create_app(settings, static_dir=None)) as client:
        data = client.get("/api/health").json()["data"]
    assert data["logs_bytes"] == 3 * MB
    assert data["recordings_bytes"] == MB
    assert (data["logs_keep_bytes"], data["captures_keep_bytes"]) == (100 * MB, 7 * MB)
    assert data["min_free_bytes"] == 512 * MB
    # everything: the logs, the recording, the audit log and timeline databases, the scope's
    assert data["total_bytes"] >= 4 * MB + data["captures_bytes"]
    assert 0 < data["free_bytes"] <= shutil.disk_usage(tmp_path).total


def test_a_measurement_is_reused_until_forgotten(tmp_path: Path) -> None:
    meter = UsageMeter(tmp_path, logs_keep_mb=1, captures_keep_mb=1, min_free_mb=0)
    assert meter.measure().total_bytes == 0
    (tmp_path / "scope").mkdir()
    (tmp_path / "scope" / "capture.rrd").write_bytes(b"x" * 100)
    assert asyncio.run(meter.usage()).captures_bytes == 0  # measured a moment ago
    meter.forget()
    assert asyncio.run(meter.usage()).captures_bytes == 100
