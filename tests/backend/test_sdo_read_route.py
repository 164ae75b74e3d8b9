"""GET /api/nodes/{node}/sdo/{index}/{subindex} answers through its prebuilt handler
(api/sdo.py ReadRoute) exactly as FastAPI's own handler does, for reads, errors and the path
values only FastAPI checks; and the API's routes sit flat on the app's router (app.py)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import fastapi.routing
import pytest
from fastapi.routing import APIRoute, APIWebSocketRoute
from fastapi.testclient import TestClient

from servodesk.api.deps import get_services
from servodesk.api.route_table import api_routers
from servodesk.app import create_app
from servodesk.settings import Settings

PATHS = [
    "/api/nodes/1/sdo/1008/0",  # a string
    "/api/nodes/1/sdo/2006/08",  # a number with a name from the profile
    "/api/nodes/3/sdo/6041/00",
    "/api/nodes/1/sdo/6041/0",
    "/api/nodes/1/sdo/7777/0",  # SDO abort: 409 with the abort code
    "/api/nodes/42/sdo/1000/0",  # no such node: 404
    "/api/nodes/001/sdo/1000/0",  # values FastAPI still takes: its own handler answers
    "/api/nodes/+1/sdo/1000/0",
    "/api/nodes/0/sdo/1000/0",  # refused by FastAPI's checks: 422 in the documented shape
    "/api/nodes/128/sdo/1000/0",
    "/api/nodes/x/sdo/1000/0",
    "/api/nodes/1/sdo/zz/0",
    "/api/nodes/1/sdo/10080/0",
    "/api/nodes/1/sdo/1008/100",
    "/api/nodes/1/sdo/1008/%0A",
    "/api/nodes/1/sdo/%D9%A1008/0",  # an Arabic-Indic digit
    "/api/nodes/1/sdo/1008/0?since=3",
]


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path_factory.mktemp("data"))
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


def answer(response: Any) -> tuple[int, str | None, bytes]:
    return response.status_code, response.headers.get("content-type"), response.content


def test_the_prebuilt_handler_answers_as_fastapi_does(client: TestClient) -> None:
    app: Any = client.app
    requests = [("GET", path) for path in PATHS] + [("HEAD", PATHS[0]), ("POST", PATHS[0])]
    ours = {r: answer(client.request(*r)) for r in requests}
    # any dependency override sends the route to FastAPI's own handler
    app.dependency_overrides[get_services] = get_services
    try:
        fastapis = {r: answer(client.request(*r)) for r in requests}
    finally:
        app.dependency_overrides.clear()
    assert ours == fastapis
    assert ours["GET", "/api/nodes/1/sdo/1008/0"][:2] == (200, "application/json")
    assert ours["GET", "/api/nodes/1/sdo/7777/0"][0] == 409
    assert ours["GET", "/api/nodes/0/sdo/1000/0"][0] == 422


def test_a_read_solves_no_dependencies(client: TestClient, monkeypatch: pytest.MonkeyPatch) -> None:
    async def refuse(**_: Any) -> None:
        raise AssertionError("FastAPI's dependency solving ran for a read")

    monkeypatch.setattr(fastapi.routing, "solve_dependencies", refuse)
    assert client.get("/api/nodes/1/sdo/1008/0").json()["value"] == "DVS_CANOPEN"


def test_every_api_route_is_on_the_app_router_itself(tmp_path: Path) -> None:
    app = create_app(Settings(simulated=True, data_dir=tmp_path), static_dir=None)
    api = [r for r in app.router.routes if isinstance(r, APIRoute | APIWebSocketRoute)]
    assert all(r.path.startswith("/api/") for r in api)
    assert len(api) == sum(len(router.routes) for router in api_routers())
    assert "/api/ws" in {r.path for r in api if isinstance(r, APIWebSocketRoute)}
    assert "/api/nodes/{node}/sdo/{index}/{subindex}" in app.openapi()["paths"]
