"""Access control through the real app with the simulated drives: tokens configured, the API
answers 401 without a valid one, 403 for a role that may not, and quick stop to everyone; the
browser logs in for an HttpOnly, SameSite=Strict cookie; the live WebSocket needs a login and
our own origin; a login is rate limited; no token is logged."""

from __future__ import annotations

import logging
from collections.abc import Iterator
from pathlib import Path

import pytest
from fastapi.testclient import TestClient
from pydantic import SecretStr
from starlette.testclient import WebSocketTestSession
from starlette.websockets import WebSocketDisconnect

from servodesk.app import create_app
from servodesk.settings import Settings

ENGINEER = "eng-secret-0123456789"
OPERATOR = "op-secret-0123456789"
VIEWER = "view-secret-0123456789"
TOKENS = f"engineer={ENGINEER},operator={OPERATOR},viewer={VIEWER}"


def bearer(token: str) -> dict[str, str]:
    return {"authorization": f"Bearer {token}"}


@pytest.fixture(scope="module")
def app_client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    settings = Settings(
        simulated=True, data_dir=tmp_path_factory.mktemp("data"), tokens=SecretStr(TOKENS)
    )
    with TestClient(create_app(settings, static_dir=None)) as client:
        yield client


@pytest.fixture
def client(app_client: TestClient) -> TestClient:
    app_client.cookies.clear()
    return app_client


def test_no_token_is_401_with_how_to_log_in(client: TestClient) -> None:
    response = client.get("/api/nodes")
    assert response.status_code == 401
    assert response.headers["www-authenticate"] == "Bearer"
    body = response.json()
    assert body["error"] == "unauthorized"
    assert "Authorization: Bearer" in body["message"]
    # writes too, and nothing was written
    refused = client.put("/api/nodes/1/sdo/6081/0", json={"value": 777})
    assert refused.status_code == 401
    value = client.get("/api/nodes/1/sdo/6081/0", headers=bearer(VIEWER)).json()["value"]
    assert value != 777


def test_a_wrong_token_is_401(client: TestClient) -> None:
    response = client.get("/api/nodes", headers=bearer(ENGINEER + "x"))
    assert response.status_code == 401
    assert "not valid" in response.json()["message"]


def test_open_routes_need_no_login(client: TestClient) -> None:
    assert client.get("/api/health").status_code == 200
    assert client.get("/api/openapi.json").status_code == 200


def test_viewer_reads_but_may_not_write_or_move(client: TestClient) -> None:
    viewer = bearer(VIEWER)
    assert client.get("/api/nodes/1/sdo/6081/0", headers=viewer).status_code == 200
    write = client.put("/api/nodes/1/sdo/6081/0", json={"value": 1}, headers=viewer)
    assert write.status_code == 403
    assert write.json()["error"] == "forbidden"
    assert (write.json()["role"], write.json()["required"]) == ("viewer", "engineer")
    enable = client.post("/api/nodes/1/drive/enable", headers=viewer)
    assert enable.status_code == 403
    assert enable.json()["required"] == "operator"
    assert "the viewer role may not" in enable.json()["message"]
    jog = client.post("/api/nodes/1/jog", json={"mode": "pv", "velocity_rpm": 10}, headers=viewer)
    assert jog.status_code == 403


def test_quick_stop_is_allowed_to_every_role(client: TestClient) -> None:
    for token in (VIEWER, OPERATOR, ENGINEER):
        response = client.post("/api/nodes/1/drive/quick-stop", headers=bearer(token))
        assert response.status_code == 200, response.text
        assert client.post("/api/quick-stop", headers=bearer(token)).status_code == 200


def test_operator_moves_but_may_not_configure(client: TestClient) -> None:
    operator = bearer(OPERATOR)
    enable = client.post("/api/nodes/3/drive/enable", headers=operator)
    assert enable.status_code == 200, enable.text
    assert client.post("/api/nodes/3/drive/disable", headers=operator).status_code == 200
    for method, path, body in [
        ("PUT", "/api/nodes/3/sdo/6081/0", {"value": 5}),
        ("PUT", "/api/nodes/1/params/PA-14", {"value": 4}),
        ("POST", "/api/nodes/3/nmt", {"command": "start"}),
        ("POST", "/api/nodes/3/store", {"confirm": True}),
    ]:
        response = client.request(method, path, json=body, headers=operator)
        assert response.status_code == 403, (path, response.text)
        assert response.json()["required"] == "engineer"


def test_engineer_may_configure(client: TestClient) -> None:
    response = client.put("/api/nodes/3/sdo/6081/0", json={"value": 4321}, headers=bearer(ENGINEER))
    assert response.status_code == 200
    assert response.json()["value"] == 4321


def test_browser_login_sets_a_strict_httponly_cookie_and_logout_ends_it(
    client: TestClient,
) -> None:
    assert client.get("/api/session").status_code == 401
    login = client.post("/api/login", json={"token": OPERATOR})
    assert login.status_code == 200
    assert login.json() == {
        "user": "operator",
        "role": "operator",
        "auth_required": True,
        "may": {"operate": True, "configure": False},
    }
    cookie = login.headers["set-cookie"]
    assert "servodesk_session=" in cookie
    assert "HttpOnly" in cookie
    assert "SameSite=strict" in cookie or "SameSite=Strict" in cookie
    assert "Secure" not in cookie  # plain HTTP here; see the TLS test
    assert OPERATOR not in cookie  # the cookie holds a session id, not the token
    assert client.get("/api/session").json()["role"] == "operator"
    assert client.post("/api/nodes/3/drive/disable").status_code == 200
    assert client.put("/api/nodes/3/sdo/6081/0", json={"value": 1}).status_code == 403
    assert client.post("/api/logout").status_code == 204
    # the server forgot the session: the old cookie value does not work either
    client.cookies.set("servodesk_session", cookie.split(";")[0].split("=", 1)[1])
    expired = client.get("/api/session")
    assert expired.status_code == 401
    assert "log in again" in expired.json()["message"]


def test_login_with_a_wrong_token_then_rate_limited(tmp_path: Path) -> None:
    settings = Settings(simulated=False, data_dir=tmp_path, tokens=SecretStr(TOKENS))
    with TestClient(create_app(settings, static_dir=None)) as client:
        for _ in range(5):
            wrong = client.post("/api/login", json={"token": "guess-0123456789"})
            assert wrong.status_code == 401
            assert wrong.json()["error"] == "unauthorized"
        limited = client.post("/api/login", json={"token": ENGINEER})  # even the right one
        assert limited.status_code == 429
        body = limited.json()
        assert body["error"] == "rate_limited"
        assert 1 <= body["retry_after_s"] <= 60
        assert limited.headers["retry-after"] == str(body["retry_after_s"])
        assert "try again in" in body["message"]


def test_wrong_bearer_tokens_count_like_failed_logins(tmp_path: Path) -> None:
    settings = Settings(simulated=False, data_dir=tmp_path, tokens=SecretStr(TOKENS))
    with TestClient(create_app(settings, static_dir=None)) as client:
        for n in range(5):
            wrong = client.get("/api/session", headers=bearer(f"guess-{n:012d}"))
            assert wrong.status_code == 401
        for attempt in (
            client.get("/api/session", headers=bearer(ENGINEER)),  # even the right one
            client.post("/api/login", json={"token": ENGINEER}),  # and by logging in
        ):
            assert attempt.status_code == 429, attempt.text
            body = attempt.json()
            assert body["error"] == "rate_limited"
            assert 1 <= body["retry_after_s"] <= 60
            assert attempt.headers["retry-after"] == str(body["retry_after_s"])


def test_cookie_is_secure_when_served_over_tls(tmp_path: Path) -> None:
    cert = tmp_path / "cert.pem"
    settings = Settings(
        simulated=False, data_dir=tmp_path, tokens=SecretStr(TOKENS), tls_cert=cert, tls_key=cert
    )
    with TestClient(create_app(settings, static_dir=None)) as client:
        login = client.post("/api/login", json={"token": VIEWER})
        assert "Secure" in login.headers["set-cookie"]


def test_live_socket_needs_a_login(client: TestClient) -> None:
    with pytest.raises(WebSocketDisconnect) as refused, client.websocket_connect("/api/ws") as ws:
        ws.receive_json()
    assert refused.value.code == 1008
    assert client.post("/api/login", json={"token": VIEWER}).status_code == 200
    with client.websocket_connect("/api/ws") as ws:
        ws.send_json({"type": "ping"})
        while (message := ws.receive_json())["type"] != "pong":
            pass
        # a viewer's socket may quick-stop (stopping is everyone's)
        ws.send_json({"type": "quick_stop", "node": 1})
        ws.send_json({"type": "ping"})
        while (message := ws.receive_json())["type"] not in ("pong", "error"):
            pass
        assert message["type"] == "pong"


def login_cookie(client: TestClient, token: str) -> dict[str, str]:
    """A fresh login's cookie as a header (the client's own jar is left empty)."""
    answer = client.post("/api/login", json={"token": token})
    assert answer.status_code == 200
    sid = answer.cookies["servodesk_session"]
    client.cookies.clear()
    return {"cookie": f"servodesk_session={sid}"}


def closed_by_server(ws: WebSocketTestSession) -> int:
    """Read until the server closes the socket; its close code."""
    for _ in range(10_000):  # status pushes may come first
        try:
            ws.receive_json()
        except WebSocketDisconnect as closed:
            return closed.code
    raise AssertionError("the socket stayed open")


def test_logging_out_closes_that_logins_live_sockets_only(client: TestClient) -> None:
    mine, other = login_cookie(client, OPERATOR), login_cookie(client, OPERATOR)
    with (
        client.websocket_connect("/api/ws", headers=mine) as ws,
        client.websocket_connect("/api/ws", headers=other) as kept,
    ):
        ws.send_json({"type": "ping"})
        while ws.receive_json()["type"] != "pong":
            pass
        assert client.post("/api/logout", headers=mine).status_code == 204
        assert closed_by_server(ws) == 1008  # the page shows its login again
        kept.send_json({"type": "ping"})  # the same user's other login goes on
        while kept.receive_json()["type"] != "pong":
            pass
    assert client.get("/api/session", headers=other).status_code == 200


def test_logins_evict_only_that_users_oldest(client: TestClient) -> None:
    engineer = login_cookie(client, ENGINEER)
    first = login_cookie(client, VIEWER)
    with client.websocket_connect("/api/ws", headers=first) as ws:
        later = [login_cookie(client, VIEWER) for _ in range(25)]
        assert closed_by_server(ws) == 1008  # evicted: its socket closes too
    assert client.get("/api/session", headers=first).status_code == 401
    assert client.get("/api/session", headers=engineer).json()["user"] == "engineer"
    working = [client.get("/api/session", headers=c).status_code for c in later]
    assert working == [401] * 5 + [200] * 20  # 20 logins per user at most


def test_live_socket_from_a_foreign_origin_is_refused(client: TestClient) -> None:
    assert client.post("/api/login", json={"token": ENGINEER}).status_code == 200
    foreign = {"origin": "http://evil.example"}
    with (
        pytest.raises(WebSocketDisconnect) as refused,
        client.websocket_connect("/api/ws", headers=foreign) as ws,
    ):
        ws.receive_json()
    assert refused.value.code == 1008


def test_no_token_reaches_the_log(client: TestClient, caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.DEBUG)
    client.get("/api/nodes", headers=bearer(ENGINEER))
    client.post("/api/login", json={"token": OPERATOR})
    client.post("/api/login", json={"token": "wrong-token-0123456789"})
    client.put("/api/nodes/3/sdo/6081/0", json={"value": 12}, headers=bearer(ENGINEER))
    for secret in (ENGINEER, OPERATOR, "wrong-token-0123456789"):
        assert secret not in caplog.text
    audit = client.get("/api/audit", headers=bearer(ENGINEER)).json()
    assert all(ENGINEER not in str(entry) for entry in audit)
    assert audit[0]["user"] == "engineer"  # the last write names who made it


def test_settings_do_not_show_the_tokens() -> None:
    settings = Settings(tokens=SecretStr(TOKENS))
    assert ENGINEER not in repr(settings)
    assert ENGINEER not in str(settings.model_dump())


def test_host_and_origin_are_checked_against_the_served_names(tmp_path: Path) -> None:
    settings = Settings(
        simulated=False,
        data_dir=tmp_path,
        tokens=SecretStr(TOKENS),
        bind="0.0.0.0",
        allowed_hosts="servodesk.plant.example",
    )
    app = create_app(settings, static_dir=None)
    with TestClient(app, base_url="http://servodesk.plant.example:8000") as client:
        assert client.get("/api/health").status_code == 200
        other = client.get("/api/health", headers={"host": "evil.example:8000"})
        assert other.status_code == 400
        assert "servodesk.plant.example" in other.json()["message"]
        own = {"origin": "http://servodesk.plant.example:8000", **bearer(ENGINEER)}
        assert client.post("/api/nodes/1/drive/quick-stop", headers=own).status_code != 403
        foreign = {"origin": "http://evil.example:8000", **bearer(ENGINEER)}
        refused = client.post("/api/nodes/1/drive/quick-stop", headers=foreign)
        assert refused.status_code == 403
        assert refused.json()["error"] == "cross_origin"
