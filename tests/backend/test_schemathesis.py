"""The API against its own schema: schemathesis generates valid and invalid requests for every
operation and checks every answer (no server error, status and body as the schema declares,
invalid input refused, valid input accepted), against the real server with the simulated
drives. Examples are bounded and derandomized so the run is the same on every machine."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import httpx
import pytest
import schemathesis
from hypothesis import HealthCheck, settings
from schemathesis.specs.openapi.checks import positive_data_acceptance

from servodesk.app import create_app
from tests.live_server import serve_simulated

# Operations left out, and why: each would take the bus or a drive away from the rest of the
# run (a generated bus configuration disconnects the simulated drives; a node-id or bitrate
# change moves a drive off the bus; "reset" broadcasts restart every drive mid-request). An
# interpolated stream runs for its whole duration (up to 30 s per example): tested on its own.
EXCLUDED = (
    "POST /api/bus/connect",
    "POST /api/bus/disconnect",
    "POST /api/nodes/{node}/change-node-id",
    "POST /api/nodes/{node}/change-bitrate",
    "POST /api/nmt",
    "POST /api/nodes/{node}/drive/ip-stream",
)
EXAMPLES = 12
# In a process of its own (`make pytest-fuzz`), not under pytest-xdist: there schemathesis
# collects the operations as one item that makes a few dozen requests instead of one item per
# operation (the bar below is 1000).
pytestmark = pytest.mark.fuzz
# Refusals a schema cannot express: a request of the right shape naming a parameter the drive
# does not have, or a value out of the drive's range (422 invalid_value), or a change that
# needs confirm=true (428). Schema validation itself (422 invalid_request) must never refuse
# schema-valid data: that is checked by `passes_validation` instead.
SEMANTIC_REFUSALS = {422: "invalid_value", 428: "confirmation_required"}

# The run is made as an engineer with tokens configured, so every request also passes the
# access check; the least number of requests it must make (the Trust issue's bar).
TOKEN = "engineer-fuzz-0123456789"
AUTH = {"authorization": f"Bearer {TOKEN}"}
MIN_REQUESTS = 1000

_openapi = create_app(static_dir=None).openapi()
schema = schemathesis.openapi.from_dict(_openapi)
# (METHOD, path template) of every operation that writes an audit entry (x-audited)
AUDITED = {
    (method.upper(), path)
    for path, item in _openapi["paths"].items()
    for method, operation in item.items()
    if operation.get("x-audited")
}
# what the run sent: requests in all, and those the audit log must hold an entry for
SENT = {"requests": 0, "audited": 0}


@pytest.fixture(scope="module")
def base_url(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    data = tmp_path_factory.mktemp("data")
    # The login cases guess tokens from the engineer's own address: guesses and the engineer's
    # bearer token share one limit (docs/security.md), set high here so the run goes on.
    overrides = {"tokens": f"engineer={TOKEN}", "token_failures_per_client": 100_000}
    overrides["token_failures_overall"] = 1_000_000
    with serve_simulated(data, static_dir=None, overrides=overrides) as url:
        yield url


def passes_validation(
    ctx: schemathesis.CheckContext, response: schemathesis.Response, case: schemathesis.Case[Any]
) -> bool | None:
    """Schema-valid data is never refused by request validation; other refusals name the
    reason the drive or the tool has (see SEMANTIC_REFUSALS)."""
    meta = case.meta
    if meta is None or not meta.generation.mode.is_positive or response.status_code < 400:
        return None
    body = response.json()
    if case.path == "/api/login" and response.status_code in (401, 429):
        # a well-formed token that is not one of ours, and the rate limit that follows
        assert body["error"] in ("unauthorized", "rate_limited"), body
        return None
    if response.status_code in SEMANTIC_REFUSALS:
        assert body["error"] in (SEMANTIC_REFUSALS[response.status_code], "identity_mismatch"), (
            f"schema-valid request refused: {response.status_code} {body}"
        )
    else:
        assert response.status_code in (404, 409, 502, 503, 504), (
            f"schema-valid request refused: {response.status_code} {body}"
        )
    return None


@schema.exclude(name=list(EXCLUDED)).parametrize()
@settings(
    max_examples=EXAMPLES,
    deadline=None,
    derandomize=True,
    suppress_health_check=list(HealthCheck),
)
def test_api_conforms_to_its_schema(case: schemathesis.Case[Any], base_url: str) -> None:
    response = case.call_and_validate(
        base_url=base_url,
        headers=AUTH,
        timeout=30,
        excluded_checks=[positive_data_acceptance],
        additional_checks=[passes_validation],
    )
    SENT["requests"] += 1
    routed = not (response.status_code == 404 and response.json().get("error") == "not_found")
    if (case.method.upper(), case.path) in AUDITED and routed:
        SENT["audited"] += 1


def test_the_run_was_large_enough_and_every_write_is_audited(base_url: str) -> None:
    """Runs after the generated cases (same module, same server): at least MIN_REQUESTS were
    made, and the audit log holds one entry for each request to a writing route."""
    assert SENT["requests"] >= MIN_REQUESTS, SENT
    entries = []
    before: int | None = None
    with httpx.Client(base_url=base_url, headers=AUTH, timeout=30) as client:
        while True:
            params = {"limit": 1000, **({"before": before} if before else {})}
            page = client.get("/api/audit", params=params).json()
            if not page:
                break
            entries += page
            before = page[-1]["id"]
    # the server's own writes (a jog it stopped when the keep-alives stopped) are by "servodesk"
    requested = [entry for entry in entries if entry["user"] != "servodesk"]
    by_tool = len(entries) - len(requested)
    print(
        f"schemathesis: {SENT['requests']} requests, {SENT['audited']} audited writes, "
        f"{by_tool} entries by the server itself"
    )
    assert len(requested) == SENT["audited"], SENT
    assert all(entry["result"] != "pending" for entry in entries)
    assert {entry["user"] for entry in requested} == {"engineer"}
