"""Which role each request needs: one table, default deny (docs/security.md).

Reading is the viewer's; stopping is everyone's, always (quick stop, stopping a jog); moving the
axis and running the scope are the operator's; everything else that changes a drive or the
tool's configuration is the engineer's, including any state-changing route this table does
not name, so a new route is safe until it is placed here. The frontend's own files are open
(the login page must load); the API, its WebSocket and the rerun viewer behind the app are not.
"""

from __future__ import annotations

import re

from servodesk.access.actor import Role

READS = frozenset({"GET", "HEAD", "OPTIONS"})
_N = r"/api/nodes/[^/]+"
_C = r"/api/commissioning/[^/]+"

# Reachable without logging in: logging in, the health check monitors poll, and the API's
# own description (it holds no data).
OPEN = re.compile(r"/api/(login|logout|health|openapi\.json|docs)(/.*)?")

# (methods, path) a viewer may use although they are not plain reads.
_EVERYONE = [
    ("POST", rf"/api/quick-stop|{_N}/drive/quick-stop"),  # stopping is never refused
    ("DELETE", r"/api/jog/[^/]+"),  # stopping a jog
    # computations that send nothing to a drive and change nothing
    ("POST", rf"{_N}/pdos/validate|/api/scope/plan|{_N}/compare|/api/od/check|/api/logs/decode"),
    # reading: scanning the bus, uploading every entry, watching the PDOs that pass, the field
    # check of a drive against its commissioning record (reads the drive, like compare)
    ("POST", rf"/api/scan|{_N}/upload-all|{_N}/pdos/live|/api/commissioning/check"),
    ("DELETE", rf"/api/jobs/[^/]+|{_N}/pdos/live"),
    # rerun's viewer streams a recording over gRPC-web POSTs: reading
    ("POST", r"/rerun\.sdk_comms\.[^/]+/[^/]+"),
]
_OPERATOR = [
    (
        "POST",
        rf"{_N}/drive/(enable|disable|command|fault-reset|move|move-queue|home|ip-stream)"
        rf"|{_N}/jog|/api/jog/[^/]+/keepalive|{_N}/faults/reset|/api/scope/captures|/api/recording",
    ),
    ("PUT", rf"{_N}/drive/limits"),
    # commissioning: records live in the tool; running a step that only reads or moves the axis
    # as a test (stop_test, test_move: the operator's, like jogs), signing off.
    # store_verify stores and resets the drive: the engineer's (not listed here)
    ("POST", rf"{_N}/commissioning"),
    (
        "POST",
        rf"{_C}/steps/(identity|communication|parameters|pdo|limits|stop_test|test_move|homing)/run",
    ),
    ("PUT", rf"{_C}/steps/[^/]+"),
    ("POST|DELETE", rf"{_N}/drive/controller"),
    ("DELETE", r"/api/scope/captures/[^/]+|/api/recording|/api/logs/[^/]+"),
]


def _compile(rules: list[tuple[str, str]]) -> list[tuple[frozenset[str], re.Pattern[str]]]:
    return [(frozenset(methods.split("|")), re.compile(path)) for methods, path in rules]


_RULES = [(Role.VIEWER, rule) for rule in _compile(_EVERYONE)] + [
    (Role.OPERATOR, rule) for rule in _compile(_OPERATOR)
]


def protected(path: str) -> bool:
    """The API, its WebSocket and the viewer need a login; the frontend's files do not."""
    if OPEN.fullmatch(path):
        return False
    return path.startswith(("/api/", "/rerun")) or path == "/api"


def required_role(method: str, path: str) -> Role | None:
    """The least role that may send `method path`; None: no login needed."""
    if not protected(path):
        return None
    method = method.upper()
    if method in READS or method == "WEBSOCKET":
        return Role.VIEWER
    for role, (methods, pattern) in _RULES:
        if method in methods and pattern.fullmatch(path):
            return role
    return Role.ENGINEER


WHAT_NEEDS = {
    Role.VIEWER: "logging in",
    Role.OPERATOR: "the operator or engineer role",
    Role.ENGINEER: "the engineer role",
}
