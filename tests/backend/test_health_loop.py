"""GET /api/health says how late the event loop runs (p50 / p99 / max over the last minute)."""

from __future__ import annotations

import time

from fastapi.testclient import TestClient


def test_health_reports_the_loop_lag(client: TestClient) -> None:
    time.sleep(0.3)  # a few of the watch's 50 ms ticks
    loop = client.get("/api/health").json()["loop"]
    assert loop["samples"] >= 2
    assert loop["window_s"] == 60
    assert 0 <= loop["p50_ms"] <= loop["p99_ms"] <= loop["max_ms"]
