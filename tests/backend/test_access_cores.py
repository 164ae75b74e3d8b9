"""The pure parts of access control, table-tested: which role each route needs, token parsing
and lookup, login sessions and the login rate limit."""

from __future__ import annotations

from pathlib import Path

import pytest

from servodesk.access.actor import Role
from servodesk.access.policy import required_role
from servodesk.access.sessions import LoginLimiter, SessionStore
from servodesk.access.tokens import TokenConfigError, TokenTable

V, OP, E = Role.VIEWER, Role.OPERATOR, Role.ENGINEER


@pytest.mark.parametrize(
    ("method", "path", "role"),
    [
        # open: the frontend's files, logging in, health, the API description
        ("GET", "/", None),
        ("GET", "/assets/index-abc.js", None),
        ("GET", "/nodes/1/drive", None),  # a page of the single-page app
        ("POST", "/api/login", None),
        ("POST", "/api/logout", None),
        ("GET", "/api/health", None),
        ("GET", "/api/openapi.json", None),
        # reading is the viewer's
        ("GET", "/api/session", V),
        ("GET", "/api/nodes", V),
        ("GET", "/api/nodes/1/sdo/6041/0", V),
        ("GET", "/api/audit", V),
        ("HEAD", "/api/nodes/1/drive", V),
        ("WEBSOCKET", "/api/ws", V),
        ("GET", "/rerun/index.html", V),
        ("POST", "/rerun.sdk_comms.v1alpha1.MessageProxyService/ReadMessages", V),
        # stopping is everyone's
        ("POST", "/api/quick-stop", V),
        ("POST", "/api/nodes/3/drive/quick-stop", V),
        ("DELETE", "/api/jog/abc", V),
        # computations and reads sent as POST
        ("POST", "/api/nodes/1/pdos/validate", V),
        ("POST", "/api/scope/plan", V),
        ("POST", "/api/scan", V),
        ("POST", "/api/nodes/1/upload-all", V),
        ("POST", "/api/od/check", V),
        # moving, fault reset, scope: the operator's
        ("POST", "/api/nodes/1/drive/enable", OP),
        ("POST", "/api/nodes/1/drive/disable", OP),
        ("POST", "/api/nodes/1/drive/fault-reset", OP),
        ("POST", "/api/nodes/1/drive/move", OP),
        ("POST", "/api/nodes/1/drive/home", OP),
        ("POST", "/api/nodes/1/drive/ip-stream", OP),
        ("PUT", "/api/nodes/1/drive/limits", OP),
        ("POST", "/api/nodes/1/drive/controller", OP),
        ("DELETE", "/api/nodes/1/drive/controller", OP),
        ("POST", "/api/nodes/1/jog", OP),
        ("POST", "/api/jog/abc/keepalive", OP),
        ("POST", "/api/nodes/1/faults/reset", OP),
        ("POST", "/api/scope/captures", OP),
        ("DELETE", "/api/scope/captures/4", OP),
        ("DELETE", "/api/logs/0123456789abcdef0123456789abcdef", OP),
        ("DELETE", "/api/nodes/1", E),
        ("POST", "/api/recording", OP),
        # configuration: the engineer's
        ("PUT", "/api/nodes/1/sdo/6081/0", E),
        ("PUT", "/api/nodes/1/params/PA-14", E),
        ("PUT", "/api/nodes/1/pdos", E),
        ("POST", "/api/nodes/1/dcf", E),
        ("POST", "/api/nodes/1/store", E),
        ("POST", "/api/nodes/1/restore-defaults", E),
        ("POST", "/api/nodes/1/nmt", E),
        ("POST", "/api/nmt", E),
        ("POST", "/api/nodes/1/change-node-id", E),
        ("POST", "/api/nodes/1/change-bitrate", E),
        ("DELETE", "/api/nodes/1/faults/device-history", E),
        ("POST", "/api/nodes/1/od", E),
        ("POST", "/api/bus/connect", E),
        ("PUT", "/api/sync", E),
        ("POST", "/api/audit/4/undo", E),
        # default deny: a state-changing route nobody placed is the engineer's
        ("POST", "/api/some/new/route", E),
        ("PATCH", "/api/nodes/1/drive/limits", E),
        # no sneaking past the patterns with extra segments
        ("POST", "/api/nodes/1/drive/quick-stop/../../sdo/6081/0", E),
        ("POST", "/api/nodes/1/drive/enable/x", E),
    ],
)
def test_required_role(method: str, path: str, role: Role | None) -> None:
    assert required_role(method, path) == role


def test_tokens_from_the_environment_variable() -> None:
    table = TokenTable.load(
        "engineer=eng-0123456789,operator=op-0123456789, viewer = view-0123456789", None
    )
    assert len(table) == 3
    found = table.lookup("op-0123456789")
    assert found is not None
    assert (found.user, found.role) == ("operator", Role.OPERATOR)
    viewer = table.lookup("view-0123456789")
    assert viewer is not None
    assert viewer.role is Role.VIEWER
    assert table.lookup("op-012345678") is None  # a prefix is not the token
    assert table.lookup("") is None


def test_tokens_from_a_file_with_user_names(tmp_path: Path) -> None:
    path = tmp_path / "tokens"
    path.write_text("# plant tokens\n\nalice:engineer=alice-token-123\nbob:viewer=bob-token-456\n")
    table = TokenTable.load(None, path)
    alice = table.lookup("alice-token-123")
    assert alice is not None
    assert (alice.user, alice.role) == ("alice", Role.ENGINEER)


@pytest.mark.parametrize(
    ("text", "complaint"),
    [
        ("engineer", "expected role=token"),
        ("admin=0123456789abcdef", "unknown role 'admin'"),
        ("engineer=short", "shorter than 12 characters"),
        (":engineer=0123456789abcdef", "empty user name"),
        ("engineer=0123456789abcdef,viewer=0123456789abcdef", "the same token is given twice"),
    ],
)
def test_bad_token_configuration_says_what_is_wrong(text: str, complaint: str) -> None:
    with pytest.raises(TokenConfigError, match=complaint):
        TokenTable.load(text, None)


def test_an_unreadable_tokens_file_is_named(tmp_path: Path) -> None:
    with pytest.raises(TokenConfigError, match="cannot read the tokens file"):
        TokenTable.load(None, tmp_path / "missing")


def test_no_tokens_configured() -> None:
    assert not TokenTable.load(None, None).configured
    assert not TokenTable.load(" , ", None).configured


def test_sessions_expire_and_end() -> None:
    store = SessionStore(max_age_s=-1)  # already expired
    assert store.get(store.create("alice", Role.ENGINEER)) is None
    store = SessionStore(max_sessions=2)
    first = store.create("a", Role.VIEWER)
    second = store.create("b", Role.VIEWER)
    third = store.create("c", Role.VIEWER)
    assert store.get(first) is None  # the oldest went to make room
    assert store.get(second) is not None
    assert store.get(third) is not None
    store.end(second)
    assert store.get(second) is None
    assert first != second != third
    assert len(third) >= 40


def test_sessions_are_bounded_per_user_and_watchers_hear_every_end() -> None:
    store = SessionStore(max_per_user=2)
    ended: list[str] = []
    alice = store.create("alice", Role.ENGINEER)
    bob = store.create("bob", Role.VIEWER)
    store.watch(alice, lambda: ended.append("alice"))
    second = store.create("alice", Role.ENGINEER)
    third = store.create("alice", Role.ENGINEER)  # alice's oldest goes, not bob's
    assert store.get(alice) is None
    assert ended == ["alice"]
    assert store.get(bob) is not None
    assert (store.count("alice"), store.count("bob")) == (2, 1)
    unwatch = store.watch(second, lambda: ended.append("second"))
    assert unwatch is not None
    store.watch(third, lambda: ended.append("third"))
    unwatch()  # a closed socket stops watching: nothing calls it later
    store.end(second)
    store.end(third)
    store.end(third)  # ending twice tells once
    assert ended == ["alice", "third"]
    assert store.watch(third, lambda: None) is None  # an ended session cannot be watched
    expiring = SessionStore(max_age_s=-1)
    sid = expiring.create("carol", Role.VIEWER)
    assert expiring.watch(sid, lambda: ended.append("carol")) is None  # already expired


def test_login_limiter_per_client_and_overall() -> None:
    limiter = LoginLimiter(per_client=3, overall=5, window_s=60)
    for _ in range(3):
        assert limiter.retry_after("a", now=100.0) == 0
        limiter.failed("a", now=100.0)
    assert limiter.retry_after("a", now=110.0) == pytest.approx(50.0)
    assert limiter.retry_after("b", now=110.0) == 0  # another client may still try
    limiter.failed("b", now=110.0)
    limiter.failed("c", now=110.0)
    # five failures overall: every address that failed waits for the window
    assert limiter.retry_after("b", now=111.0) == pytest.approx(49.0)
    assert limiter.retry_after("d", now=111.0) == 0  # one that did not is not locked out
    assert limiter.retry_after("a", now=160.0) == 0  # the window has passed
    assert limiter.retry_after("b", now=171.0) == 0
