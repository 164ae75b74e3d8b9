"""Frames lost, late or repeated on the SDO path (expedited transfers, through the API).

Every request either answers the right value or fails with a clear domain error (504 `timeout`
naming the node and the object, 502 `sdo_protocol` when a repeated answer did not fit the
transfer, or 409 `sdo_abort` with its code) within a bounded time; never a hang, never a wrong
value; once the faults stop, the next request works.
"""

from __future__ import annotations

import random
import time
from collections.abc import Iterator
from typing import Any

import can
import pytest

from tests.backend.fault_rig import (
    SDO_RX,
    SDO_TX,
    FaultyApp,
    faulty_app,
    sdo_request,
    sdo_response,
)

BOUND = 2.0  # s: the longest any answer may take here (a hang shows as far more)
VENDOR_ID = {1: 4478547, 2: 768, 3: 620}  # 1018h:01 of each simulated drive
NAME = {1: "DVS_CANOPEN", 2: "Kinco Servo", 3: "C5-E-SIM"}  # 1008h (segmented upload)
PROFILE_VELOCITY = "6081/0"  # UNSIGNED32, writable on every drive
UPLOAD_ANSWER = 0x40  # scs 2 (bits 7–5): an initiate upload response


@pytest.fixture(scope="module")
def shared(tmp_path_factory: pytest.TempPathFactory) -> Iterator[FaultyApp]:
    with faulty_app(tmp_path_factory.mktemp("data")) as running:
        yield running


@pytest.fixture
def app(shared: FaultyApp) -> Iterator[FaultyApp]:
    """One app for the module (it starts in about a second); each test starts fault-free."""
    yield shared
    shared.rig.clear()
    time.sleep(0.4)  # frames a test held back arrive (and are dropped) before the next one


def read(app: FaultyApp, node: int, obj: str) -> tuple[int, dict[str, Any]]:
    answer, took = app.timed("GET", f"/api/nodes/{node}/sdo/{obj}")
    assert took < BOUND, f"GET {obj} of node {node} took {took:.2f} s"
    body: dict[str, Any] = answer.json()
    return answer.status_code, body


def write(app: FaultyApp, node: int, obj: str, value: int) -> tuple[int, dict[str, Any]]:
    answer, took = app.timed("PUT", f"/api/nodes/{node}/sdo/{obj}", json={"value": value})
    assert took < BOUND, f"PUT {obj} of node {node} took {took:.2f} s"
    body: dict[str, Any] = answer.json()
    return answer.status_code, body


def assert_clear_error(status: int, body: dict[str, Any], node: int) -> None:
    """One of the documented failures, naming the node (and, for a timeout, what was asked)."""
    assert (status, body["error"]) in {
        (504, "timeout"),
        (502, "sdo_protocol"),
        (409, "sdo_abort"),
    }, body
    assert body["node"] == node, body
    assert body["message"], body
    if body["error"] == "sdo_abort":
        assert body["abort_code"].startswith("0x"), body


def assert_works(app: FaultyApp, node: int) -> None:
    status, body = read(app, node, "1018/1")
    assert status == 200, body
    assert body["value"] == VENDOR_ID[node]
    status, body = read(app, node, "1008/0")
    assert status == 200, body
    assert body["value"] == NAME[node]


def test_a_lost_request_times_out_naming_node_and_object(app: FaultyApp) -> None:
    """Expected: the one lost request answers 504 `timeout` naming node 2 and 1018h:01h in
    well under the bound; the next request answers the right value."""
    rule = app.rig.drop("tx", sdo_request(2), times=1)
    status, body = read(app, 2, "1018/1")
    assert rule.hits == 1
    assert (status, body["error"], body["node"]) == (504, "timeout", 2)
    assert "1018h:01h" in body["message"]
    assert_works(app, 2)


def test_a_lost_answer_times_out_and_the_next_request_works(app: FaultyApp) -> None:
    """Expected: the drive's answer is lost: 504 naming node 1 and 1018h:01h; then every
    following request works."""
    rule = app.rig.drop("rx", sdo_response(1), times=1)
    status, body = read(app, 1, "1018/1")
    assert rule.hits == 1
    assert (status, body["error"], body["node"]) == (504, "timeout", 1)
    assert "1018h:01h" in body["message"]
    assert_works(app, 1)


def test_a_late_answer_within_the_timeout_gives_the_value(app: FaultyApp) -> None:
    """Expected: an answer 0.1 s late (timeout 0.2 s) still answers the right value."""
    app.rig.delay("rx", sdo_response(3), 0.1, times=1)
    status, body = read(app, 3, "1018/1")
    assert status == 200, body
    assert body["value"] == VENDOR_ID[3]


def test_an_answer_after_the_timeout_is_never_taken_for_the_next_one(app: FaultyApp) -> None:
    """Expected: node 1 answers a read of 6081h 0.3 s late (after the 0.2 s timeout), so that
    read answers 504; a write of 6081h follows at once, and the late answer arrives while the
    write's read-back waits for its own: the write answers the value it wrote (never the late
    read's old value), and so does every read after it."""

    def upload_answer(msg: can.Message) -> bool:
        return msg.arbitration_id == SDO_TX + 1 and msg.data[0] & 0xE0 == UPLOAD_ANSWER

    for value in (7, 8):
        app.rig.clear()
        app.rig.delay("rx", sdo_response(1), 0.3, times=1)  # the read's answer
        app.rig.delay("rx", upload_answer, 0.15, skip=1, times=1)  # the read-back's, in time
        status, body = read(app, 1, PROFILE_VELOCITY)
        assert (status, body["error"]) == (504, "timeout"), body
        status, body = write(app, 1, PROFILE_VELOCITY, value)
        assert status == 200, body
        assert body["value"] == value, body
        status, body = read(app, 1, PROFILE_VELOCITY)
        assert (status, body["value"]) == (200, value), body
    assert_works(app, 1)


def test_repeated_answers_never_give_a_wrong_value(app: FaultyApp) -> None:
    """Expected: every answer of node 2 arrives twice; reads of alternating objects and writes
    with their read-back each give exactly their own value or a clear error."""
    app.rig.duplicate("rx", sdo_response(2))
    for value in range(1000, 1010):
        status, body = read(app, 2, "1018/1")
        if status == 200:
            assert body["value"] == VENDOR_ID[2]
        else:
            assert_clear_error(status, body, 2)
        status, body = write(app, 2, PROFILE_VELOCITY, value)
        if status == 200:
            assert body["value"] == value, body
        else:
            assert_clear_error(status, body, 2)
    app.rig.clear()
    assert_works(app, 2)


def test_repeated_requests_are_harmless(app: FaultyApp) -> None:
    """Expected: every request to node 3 goes out twice (the drive answers each): values stay
    right, and once it stops everything works."""
    app.rig.duplicate("tx", sdo_request(3))
    for value in (111, 222, 333):
        status, body = write(app, 3, PROFILE_VELOCITY, value)
        if status == 200:
            assert body["value"] == value, body
        else:
            assert_clear_error(status, body, 3)
    app.rig.clear()
    time.sleep(0.05)  # the last repeated answer is in by now
    status, body = read(app, 3, PROFILE_VELOCITY)
    assert (status, body["value"]) == (200, 333), body
    assert_works(app, 3)


def test_random_loss_delay_and_repetition_lose_nothing(app: FaultyApp) -> None:
    """Expected: with 10 % of SDO frames (both ways) lost, 10 % of the answers 0.25 s late
    (after the 0.2 s timeout), 10 % of the requests 0.05 s late and 10 % of the answers
    repeated, each of 36 mixed requests to the three drives answers its own right value or a
    clear error within the bound; after the faults stop, every drive's value is the last one
    written (or one whose write failed after it), and every request works."""
    rng = random.Random(20240611)

    def sdo(msg: can.Message) -> bool:
        return SDO_TX < msg.arbitration_id <= SDO_TX + 3 or SDO_RX < msg.arbitration_id <= 0x603

    def chance(p: float) -> Any:
        return lambda msg: sdo(msg) and rng.random() < p

    app.rig.drop("rx", chance(0.1))
    app.rig.drop("tx", chance(0.1))
    # an answer at most 0.3 s late: within the one response time the session lets a late
    # answer pass after a timeout (an answer later still cannot be told apart in SDO)
    app.rig.delay("rx", chance(0.1), 0.25)
    app.rig.delay("tx", chance(0.1), 0.05)
    app.rig.duplicate("rx", chance(0.1))
    written: dict[int, list[int]] = {1: [100000], 2: [100000], 3: [100000]}  # ok, then failed
    failures = 0
    writes: list[tuple[int, int, int, str | None]] = []  # node, value, status, error kind
    for step in range(36):
        node = step % 3 + 1
        kind = step // 3 % 3
        if kind == 0:
            status, body = read(app, node, "1018/1")
            expected: object = VENDOR_ID[node]
        elif kind == 1:
            status, body = read(app, node, "1008/0")
            expected = NAME[node]
        else:
            expected = 5000 + step
            status, body = write(app, node, PROFILE_VELOCITY, 5000 + step)
            writes.append((node, 5000 + step, status, body.get("error")))
            if status == 200:
                written[node] = [5000 + step]
            else:
                written[node].append(5000 + step)  # may or may not have reached the drive
        if status == 200:
            assert body["value"] == expected, (step, body)
        else:
            failures += 1
            assert_clear_error(status, body, node)
    assert failures > 0  # the faults did bite
    app.rig.clear()
    time.sleep(0.35)  # frames still held back arrive (and are ignored)
    for node in (1, 2, 3):
        status, body = read(app, node, PROFILE_VELOCITY)
        assert status == 200, body
        assert body["value"] in written[node], (node, body, written[node])
        assert_works(app, node)
    # the audit log lost none of the writes: one entry each, with the result the client saw
    audit = app.client.get("/api/audit", params={"action": "sdo-write", "limit": 1000}).json()
    mine = [e for e in reversed(audit) if e["new"] in {value for _, value, _, _ in writes}]
    assert [(e["node"], e["new"]) for e in mine] == [(n, v) for n, v, _, _ in writes]
    for entry, (_, _, answered, error_kind) in zip(mine, writes, strict=True):
        assert entry["result"] == ("ok" if answered == 200 else "failed"), entry
        assert entry["error"] == error_kind, entry
