"""X-Forwarded-For is believed only from the proxies the settings name: by default any local
program could otherwise choose the address the audit log records and the login limit counts."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import httpx
import pytest

from tests.live_server import serve_simulated

SPOOFED = "10.66.66.66"


def recorded_client(base: str) -> str:
    with httpx.Client(base_url=base, timeout=10) as http:
        stop = http.post("/api/quick-stop", headers={"x-forwarded-for": SPOOFED})
        assert stop.status_code == 200, stop.text
        entries = http.get("/api/audit", params={"action": "quick-stop"}).json()
    client: str = entries[0]["client"]
    return client


@pytest.mark.parametrize(
    ("overrides", "recorded"),
    [({}, "127.0.0.1:"), ({"forwarded_allow_ips": "127.0.0.1"}, f"{SPOOFED}:")],
)
def test_the_audit_log_records_the_real_client_unless_a_proxy_is_named(
    tmp_path: Path, overrides: dict[str, Any], recorded: str
) -> None:
    with serve_simulated(tmp_path, static_dir=None, overrides=overrides) as base:
        assert recorded_client(base).startswith(recorded)
