"""Headers a hostile page or client can send: the test client's own host name is no served
host, a repeated Origin or Host is refused whatever comes second, and no page can be framed by
another site (the viewer only by ServoDesk's own Scope page)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.settings import Settings

OURS = "http://127.0.0.1:8000"


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    # as `servodesk serve` runs it: no extra host names
    settings = Settings(allowed_hosts="", data_dir=tmp_path_factory.mktemp("data"))
    with TestClient(create_app(settings, static_dir=None), base_url=OURS) as test_client:
        yield test_client


def test_the_test_clients_host_is_not_served(client: TestClient) -> None:
    answer = client.get("/api/health", headers={"host": "testserver"})
    assert answer.status_code == 400
    assert answer.json()["error"] == "bad_host"
    own_page_on_testserver = {"host": "testserver", "origin": "http://testserver"}
    assert client.post("/api/quick-stop", headers=own_page_on_testserver).status_code == 400


@pytest.mark.parametrize(
    "headers",
    [
        [("origin", "http://evil.example"), ("origin", OURS)],
        [("origin", OURS), ("origin", OURS)],
        [("host", "127.0.0.1:8000"), ("host", "evil.example")],
        [("referer", "http://evil.example/"), ("referer", f"{OURS}/")],
    ],
)
def test_a_repeated_deciding_header_is_refused(
    client: TestClient, headers: list[tuple[str, str]]
) -> None:
    # httpx merges a dict's keys: send the raw list, as a hostile client can
    answer = client.post("/api/quick-stop", headers=headers)
    assert answer.status_code == 400, answer.text
    body = answer.json()
    assert body["error"] == "bad_header"
    assert f"more than one {headers[0][0]} header" in body["message"]


def test_one_origin_of_our_own_passes(client: TestClient) -> None:
    assert client.post("/api/quick-stop", headers={"origin": OURS}).status_code != 403


@pytest.mark.parametrize("path", ["/api/health", "/api/nodes", "/api/openapi.json", "/nowhere"])
def test_no_page_or_answer_may_be_framed(client: TestClient, path: str) -> None:
    answer = client.get(path)
    assert answer.headers["x-frame-options"] == "DENY"
    assert answer.headers["content-security-policy"] == "frame-ancestors 'none'"
    assert answer.headers["x-content-type-options"] == "nosniff"


def test_refusals_are_not_framed_either(client: TestClient) -> None:
    answer = client.get("/api/health", headers={"host": "evil.example"})
    assert answer.status_code == 400
    assert answer.headers["x-frame-options"] == "DENY"


def test_the_viewer_is_framed_by_our_own_pages_only(client: TestClient) -> None:
    answer = client.get("/rerun/")  # the viewer's page, or why it is unavailable
    assert answer.headers["x-frame-options"] == "SAMEORIGIN"
    assert "frame-ancestors 'self'" in answer.headers["content-security-policy"]
    assert "frame-ancestors 'none'" not in answer.headers["content-security-policy"]


def test_the_frontend_page_cannot_be_framed(tmp_path: Path) -> None:
    static = tmp_path / "static"
    static.mkdir()
    (static / "index.html").write_text("<!doctype html><title>ServoDesk</title>")
    settings = Settings(allowed_hosts="", data_dir=tmp_path / "data")
    with TestClient(create_app(settings, static_dir=static), base_url=OURS) as page_client:
        answer = page_client.get("/drive/3")
        assert answer.status_code == 200
        assert answer.headers["x-frame-options"] == "DENY"
