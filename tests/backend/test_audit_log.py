"""The audit log through the API with the simulated drives: every write has an entry with who,
from where, the object, old → new and the result (abort code and meaning when the drive
refused); entries are filtered, exported as CSV, survive a restart, are never rewritten; a
parameter or OD write is undone from its entry, and the undo is audited itself."""

from __future__ import annotations

import csv
import io
import sqlite3
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import can
import pytest
from fastapi.testclient import TestClient

from servodesk.access.actor import Actor, Role, acting
from servodesk.app import create_app
from servodesk.audit import AuditFilter, AuditLog, Outcome
from servodesk.audit.errors import AuditUnavailableError
from servodesk.settings import Settings
from tests.backend.fault_rig import SDO_RX, faulty_app
from tests.backend.full_disk import fill, small_filesystem

UPLOAD = 0x40  # ccs 2 (bits 7–5): initiate upload request
DOWNLOAD = 0x20  # ccs 1: initiate download request


def make_client(data_dir: Path, **settings: Any) -> TestClient:
    return TestClient(
        create_app(Settings(simulated=True, data_dir=data_dir, **settings), static_dir=None)
    )


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    with make_client(tmp_path) as test_client:
        yield test_client


def newest(client: TestClient, **query: Any) -> dict[str, Any]:
    entries = client.get("/api/audit", params={"limit": 1, **query}).json()
    assert entries, "no audit entry"
    entry: dict[str, Any] = entries[0]
    return entry


def test_an_od_write_is_recorded_with_old_and_new(client: TestClient) -> None:
    before = client.get("/api/nodes/1/sdo/6081/0").json()["value"]
    started = time.time()
    assert client.put("/api/nodes/1/sdo/6081/0", json={"value": 2500}).status_code == 200
    entry = newest(client)
    assert entry["action"] == "sdo-write"
    assert (entry["node"], entry["index"], entry["subindex"]) == (1, 0x6081, 0)
    assert (entry["old"], entry["new"]) == (before, 2500)
    assert entry["result"] == "ok"
    assert (entry["user"], entry["role"]) == ("local", "engineer")
    assert entry["client"].startswith("testclient")
    assert started - 1 <= entry["time"] <= entry["finished"] <= time.time() + 1
    assert entry["undoable"] is True
    assert "6081h:00h" in entry["what"]


def test_a_refused_write_names_the_abort_code_and_its_meaning(client: TestClient) -> None:
    response = client.put("/api/nodes/1/sdo/6041/0", json={"value": 6})
    assert response.status_code == 409
    entry = newest(client)
    assert entry["result"] == "failed"
    assert entry["abort_code"] == "0x06010002"
    assert entry["message"] == "Attempt to write a read-only object"
    assert entry["error"] == "sdo_abort"
    assert entry["undoable"] is False


def test_a_parameter_write_is_recorded_by_name(client: TestClient) -> None:
    old = client.get("/api/nodes/1/params/PA-14").json()["value"]
    new = 4 if old != 4 else 0
    assert client.put("/api/nodes/1/params/PA-14", json={"value": new}).status_code == 200
    entry = newest(client)
    assert entry["action"] == "param"
    assert "PA-14" in entry["what"]
    assert (entry["old"], entry["new"]) == (old, new)


def test_a_parameter_write_reads_the_parameter_once_before_and_once_after(
    tmp_path: Path,
) -> None:
    """The audit entry and the timeline share one read of the old value: on the bus, an
    audited PA-14 write is upload (old), download, upload (read-back) and nothing more."""
    pa14 = (0x2000, 0x0F)

    def request_to(node: int, command: int) -> Callable[[can.Message], bool]:
        def match(msg: can.Message) -> bool:
            data = bytes(msg.data)
            return (
                msg.arbitration_id == SDO_RX + node
                and data[0] & 0xE0 == command
                and (int.from_bytes(data[1:3], "little"), data[3]) == pa14
            )

        return match

    with faulty_app(tmp_path) as app:
        sent: list[str] = []
        app.rig.on("tx", request_to(1, UPLOAD), lambda _m: sent.append("upload"))
        app.rig.on("tx", request_to(1, DOWNLOAD), lambda _m: sent.append("download"))
        old = app.client.get("/api/nodes/1/params/PA-14").json()["value"]
        sent.clear()
        new = 4 if old != 4 else 0
        assert app.client.put("/api/nodes/1/params/PA-14", json={"value": new}).status_code == 200
        assert sent == ["upload", "download", "upload"]
        entry = newest(app.client)
        assert (entry["old"], entry["new"]) == (old, new)
        timeline = app.client.get("/api/events", params={"node": 1}).json()["events"]
        assert any(f"{old} → {new}" in event["message"] for event in timeline), timeline


@pytest.mark.parametrize(
    ("method", "path", "body", "action"),
    [
        ("POST", "/api/nodes/3/nmt", {"command": "pre-operational"}, "nmt"),
        ("POST", "/api/nodes/3/drive/enable", None, "drive-enable"),
        ("POST", "/api/nodes/3/drive/disable", None, "drive-disable"),
        ("POST", "/api/nodes/3/drive/quick-stop", None, "quick-stop"),
        ("POST", "/api/nodes/3/faults/reset", None, "fault-reset"),
        ("POST", "/api/nodes/3/store", {"confirm": True}, "store"),
        ("DELETE", "/api/nodes/3/faults/device-history", None, "clear-history"),
    ],
)
def test_commands_are_recorded(
    client: TestClient, method: str, path: str, body: Any, action: str
) -> None:
    response = client.request(method, path, json=body)
    entry = newest(client)
    assert entry["action"] == action
    assert entry["node"] == 3
    assert entry["result"] == ("ok" if response.status_code < 400 else "failed")
    assert path in entry["what"]


def test_undo_writes_the_old_value_back_and_is_audited(client: TestClient) -> None:
    before = client.get("/api/nodes/2/sdo/6081/0").json()["value"]
    client.put("/api/nodes/2/sdo/6081/0", json={"value": 1111})
    written = newest(client)
    undo = client.post(f"/api/audit/{written['id']}/undo")
    assert undo.status_code == 200, undo.text
    entry = undo.json()
    assert entry["action"] == "undo"
    assert entry["undo_of"] == written["id"]
    assert (entry["old"], entry["new"]) == (1111, before)
    assert entry["result"] == "ok"
    assert client.get("/api/nodes/2/sdo/6081/0").json()["value"] == before
    assert newest(client)["id"] == entry["id"]


def test_undo_refuses_when_the_value_changed_since_unless_forced(client: TestClient) -> None:
    client.put("/api/nodes/2/sdo/6083/0", json={"value": 3000})
    first = newest(client)
    client.put("/api/nodes/2/sdo/6083/0", json={"value": 4000})
    refused = client.post(f"/api/audit/{first['id']}/undo")
    assert refused.status_code == 409
    assert refused.json()["error"] == "changed_since"
    assert "4000" in refused.json()["message"]
    assert client.get("/api/nodes/2/sdo/6083/0").json()["value"] == 4000  # nothing written
    forced = client.post(f"/api/audit/{first['id']}/undo", json={"force": True})
    assert forced.status_code == 200
    assert client.get("/api/nodes/2/sdo/6083/0").json()["value"] == first["old"]


def test_what_cannot_be_undone_says_why(client: TestClient) -> None:
    client.post("/api/nodes/3/drive/quick-stop")
    stop = newest(client)
    refused = client.post(f"/api/audit/{stop['id']}/undo")
    assert refused.status_code == 409
    assert refused.json()["error"] == "not_undoable"
    assert "only those can be undone" in refused.json()["message"]
    client.put("/api/nodes/1/sdo/6041/0", json={"value": 6})
    failed = newest(client)
    assert "did not complete" in client.post(f"/api/audit/{failed['id']}/undo").json()["message"]
    missing = client.post("/api/audit/999999/undo")
    assert missing.status_code == 404


def test_filters_and_paging(client: TestClient) -> None:
    for node, value in ((1, 1001), (2, 1002), (3, 1003), (1, 1004)):
        client.put(f"/api/nodes/{node}/sdo/6081/0", json={"value": value})
    node1 = client.get("/api/audit", params={"node": 1}).json()
    assert [e["new"] for e in node1] == [1004, 1001]
    page = client.get("/api/audit", params={"limit": 2}).json()
    older = client.get("/api/audit", params={"limit": 2, "before": page[-1]["id"]}).json()
    assert [e["new"] for e in page + older] == [1004, 1003, 1002, 1001]
    assert client.get("/api/audit", params={"since": time.time() + 60}).json() == []
    assert len(client.get("/api/audit", params={"action": "sdo-write"}).json()) == 4
    assert client.get("/api/audit", params={"user": "nobody"}).json() == []


def test_csv_export(client: TestClient) -> None:
    client.put("/api/nodes/1/sdo/6081/0", json={"value": 2024})
    client.put("/api/nodes/1/sdo/6041/0", json={"value": 6})
    response = client.get("/api/audit/export", params={"format": "csv", "node": 1})
    assert response.status_code == 200
    assert response.headers["content-type"].startswith("text/csv")
    assert "servodesk-audit.csv" in response.headers["content-disposition"]
    rows = list(csv.DictReader(io.StringIO(response.text)))
    assert [r["new"] for r in rows] == ["2024", "6"]  # oldest first
    assert rows[0]["index"] == "6081"
    assert rows[0]["result"] == "ok"
    assert rows[1]["abort_code"] == "0x06010002"
    assert rows[1]["result"] == "failed"
    assert rows[0]["time"].endswith("Z")


def test_the_log_survives_a_restart_and_is_never_rewritten(tmp_path: Path) -> None:
    with make_client(tmp_path) as client:
        client.put("/api/nodes/1/sdo/6081/0", json={"value": 3333})
        before = client.get("/api/audit").json()
    with make_client(tmp_path) as client:
        assert client.get("/api/audit").json() == before
    db = sqlite3.connect(tmp_path / "audit.sqlite")
    for statement in (
        "UPDATE entries SET user = 'someone else'",
        "DELETE FROM entries",
        "UPDATE results SET result = 'ok'",
        "DELETE FROM results",
        "INSERT INTO results (entry, time, result, what, undoable) "
        f"VALUES ({before[0]['id']}, 0, 'ok', 'x', 0)",  # a second result for an entry
    ):
        with pytest.raises(sqlite3.DatabaseError):
            db.execute(statement)
    db.close()


@pytest.mark.anyio
async def test_a_write_cut_off_by_a_crash_is_marked_unknown(tmp_path: Path) -> None:
    audit = AuditLog(tmp_path)
    await audit.open()
    with acting(Actor("alice", Role.ENGINEER, "10.0.0.5:4000")):
        await audit.begin("sdo-write", 1, "write node 1 6081h:00h", new=5)
    await audit.close()  # no result row: as if the server died mid-write
    reopened = AuditLog(tmp_path)
    await reopened.open()
    (row,) = await reopened.entries(AuditFilter())
    await reopened.close()
    assert (row.user, row.client, row.result) == ("alice", "10.0.0.5:4000", "unknown")
    assert row.message is not None
    assert "server stopped" in row.message


@pytest.mark.anyio
async def test_a_write_the_server_makes_by_itself_is_by_servodesk(tmp_path: Path) -> None:
    """Whoever's request armed the timer, the server's own stop is entered as "servodesk";
    a stop that fails has its error as the result."""
    audit = AuditLog(tmp_path)
    await audit.open()
    with acting(Actor("alice", Role.OPERATOR, "10.0.0.5:4000")):
        async with audit.by_tool("jog-stop", 3, "stop the jog of node 3: heartbeat lost"):
            pass
        with pytest.raises(TimeoutError):
            async with audit.by_tool("jog-stop", 2, "stop the jog of node 2: EMCY 8611h"):
                raise TimeoutError("node 2 did not answer")
    failed, stopped = await audit.entries(AuditFilter())
    await audit.close()
    assert (stopped.user, stopped.client, stopped.node, stopped.result) == (
        "servodesk",
        None,
        3,
        "ok",
    )
    assert (failed.user, failed.result, failed.message) == (
        "servodesk",
        "failed",
        "node 2 did not answer",
    )


@pytest.mark.anyio
async def test_a_closed_log_never_holds_back_a_stop(tmp_path: Path) -> None:
    audit = AuditLog(tmp_path)
    await audit.open()
    await audit.close()
    sent: list[str] = []
    async with audit.by_tool("jog-stop", 1, "stop the jog of node 1: ServoDesk is shutting down"):
        sent.append("stop")
    assert sent == ["stop"]


def test_shutting_down_releases_the_held_drives_and_says_so(tmp_path: Path) -> None:
    """A page holds node 3 (its heartbeat consumer 1016h watches ServoDesk); the server stops:
    1016h is written back, and the log has that write as the server's own, with its result."""
    page = {"X-Client-Id": "page-a", "X-Client-Name": "Alice"}
    with make_client(tmp_path) as client:
        taken = client.post("/api/nodes/3/drive/controller", headers=page, json={})
        assert taken.status_code == 200, taken.json()
        assert taken.json()["protection"]["active"] is True, taken.json()
    with make_client(tmp_path) as client:
        entries = client.get("/api/audit", params={"node": 3, "action": "release"}).json()
    assert entries, "no release entry"
    assert entries[0]["user"] == "servodesk"
    assert entries[0]["what"] == "release node 3: ServoDesk is shutting down"
    assert entries[0]["result"] == "ok"


@pytest.mark.anyio
async def test_a_full_disk_refuses_a_write_but_never_a_stop(tmp_path: Path) -> None:
    """On a file system really full: a write waiting for its entry is refused before it runs;
    a stop (wait=False) runs, then says that it is not recorded; the tool's own stop runs."""
    with small_filesystem(tmp_path / "data") as data:
        audit = AuditLog(data)
        await audit.open()
        fill(data)
        sent: list[str] = []
        with pytest.raises(AuditUnavailableError) as refused:
            async with audit.entry("param", 1, "write PA-14", Outcome.of_error):
                sent.append("write")
        assert refused.value.full
        assert refused.value.sent is None
        assert "nothing was sent" in str(refused.value)
        with pytest.raises(AuditUnavailableError) as unrecorded:
            async with audit.entry("quick-stop", 1, "quick stop of node 1", Outcome.of_error,
                                   wait=False):  # fmt: skip
                sent.append("stop")
        assert unrecorded.value.sent == "quick stop of node 1"
        assert "was sent" in str(unrecorded.value)
        async with audit.by_tool("jog-stop", 1, "stop the jog of node 1: heartbeat lost"):
            sent.append("tool stop")
        assert sent == ["stop", "tool stop"]
        await audit.close()


@pytest.mark.anyio
async def test_a_log_that_cannot_open_refuses_writes_until_there_is_space(tmp_path: Path) -> None:
    """A server restarted on a full disk still starts (its stops must work): the log refuses
    writes and opens by itself once space is freed."""
    with small_filesystem(tmp_path / "data") as data:
        first = AuditLog(data)
        await first.open()
        await first.close()  # the log of an earlier run, its WAL files gone at close
        fill(data)
        audit = AuditLog(data)
        await audit.open()  # logs the failure, does not raise
        with pytest.raises(AuditUnavailableError) as refused:
            await audit.begin("param", 1, "write PA-14")
        assert refused.value.full
        (data / "filler").unlink()
        await audit.begin("param", 1, "write PA-14")
        (row,) = await audit.entries(AuditFilter())
        await audit.close()
        assert row.action == "param"
