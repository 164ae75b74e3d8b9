"""Loopback-only serving: Host and Origin checks against DNS rebinding (DESIGN: Security).

Serving beyond loopback needs a token and roles, which the tool does not have yet, so the
server refuses to bind elsewhere (cli.py) and refuses requests naming another host.
"""

from __future__ import annotations

from urllib.parse import urlsplit

LOOPBACK_HOSTS = frozenset({"127.0.0.1", "localhost", "::1", "[::1]"})


def origin_allowed(origin: str | None, host_header: str | None) -> bool:
    """No Origin (non-browser clients) is fine; a browser Origin must be a loopback host."""
    if origin is None:
        return True
    parts = urlsplit(origin)
    hostname = parts.hostname or ""
    return hostname in LOOPBACK_HOSTS or f"[{hostname}]" in LOOPBACK_HOSTS
