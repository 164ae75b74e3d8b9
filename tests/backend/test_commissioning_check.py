"""The field check through the API on the simulated drives: a record on node 1 with a
parameter set through the API, its bundle downloaded, then the drive checked by record id and
by bundle upload, unchanged and after someone else changed the value. One app for the module
(the bundle's PDF takes a while); the tests run in file order."""

from __future__ import annotations

import io
import zipfile
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import pytest
from fastapi.testclient import TestClient
from pydantic import SecretStr

from servodesk.access.actor import Role
from servodesk.access.policy import required_role
from servodesk.app import create_app
from servodesk.settings import Settings

TOKENS = (
    "alice:engineer=alice-secret-0123456789,bob:engineer=bob-secret-0123456789,"
    "carol:viewer=carol-secret-0123456789"
)
ALICE = {"authorization": "Bearer alice-secret-0123456789"}
BOB = {"authorization": "Bearer bob-secret-0123456789"}
CAROL = {"authorization": "Bearer carol-secret-0123456789"}  # a viewer: the check only reads
PA_103 = "/api/nodes/1/params/PA-103"  # 2006:08 on the MDi-S1-C


@dataclass
class Scene:
    client: TestClient
    record_id: int
    bundle: bytes


def ok(response: Any, status: int = 200) -> Any:
    assert response.status_code == status, response.text
    return response.json()


@pytest.fixture(scope="module")
def scene(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Scene]:
    settings = Settings(
        simulated=True, data_dir=tmp_path_factory.mktemp("data"), tokens=SecretStr(TOKENS)
    )
    with TestClient(create_app(settings, static_dir=None)) as client:
        record = ok(
            client.post("/api/nodes/1/commissioning", json={"modes": ["pp"]}, headers=ALICE), 201
        )
        base = f"/api/commissioning/{record['id']}"
        ok(client.put(PA_103, json={"value": 5000}, headers=ALICE))
        for key in ("parameters", "communication", "limits"):
            ok(client.post(f"{base}/steps/{key}/run", headers=ALICE))
        bundle = client.get(f"{base}/report", params={"format": "zip"}, headers=ALICE)
        assert bundle.status_code == 200, bundle.text
        yield Scene(client, record["id"], bundle.content)


def by_record(scene: Scene, **extra: Any) -> Any:
    body = {"record_id": scene.record_id, **extra}
    return ok(scene.client.post("/api/commissioning/check", json=body, headers=CAROL))


def by_bundle(scene: Scene, node: int | None = None) -> Any:
    return ok(
        scene.client.post(
            "/api/commissioning/check",
            files={"bundle": ("bundle.zip", scene.bundle, "application/zip")},
            data={} if node is None else {"node": str(node)},
            headers=CAROL,
        )
    )


def test_unchanged_drive_does_not_differ(scene: Scene) -> None:
    for result in (by_record(scene), by_bundle(scene, node=1)):
        assert result["differs"] is False, result
        assert result["parameters"] == []
        assert result["pdos"] == []
        assert result["node"] == 1
        assert result["record_id"] == scene.record_id
        assert result["firmware"]["changed"] is False
        assert result["firmware"]["now"]["software_version"] is not None
    # the bundle's DCF brings every setting and the PDO entries; the record alone fewer
    assert by_bundle(scene)["checked_parameters"] > by_record(scene)["checked_parameters"]
    assert by_bundle(scene)["checked_pdos"] > 0


def test_a_value_changed_after_hand_over_is_named_with_who(scene: Scene) -> None:
    ok(scene.client.put(PA_103, json={"value": 5500}, headers=BOB))
    try:
        for result in (by_record(scene), by_bundle(scene)):
            assert result["differs"] is True
            (row,) = result["parameters"]
            assert (row["index"], row["subindex"], row["name"]) == (0x2006, 8, "PA-103")
            assert (row["at_handover"], row["now"], row["changed_by"]) == (5000, 5500, "bob")
            assert row["audit_id"] is not None
    finally:
        ok(scene.client.put(PA_103, json={"value": 5000}, headers=ALICE))
    assert by_record(scene)["differs"] is False  # put back: as handed over again


def test_a_file_that_is_not_a_bundle_is_refused_in_one_line(scene: Scene) -> None:
    empty = io.BytesIO()
    with zipfile.ZipFile(empty, "w") as archive:
        archive.writestr("report.html", "<p>no record</p>")
    for content in (empty.getvalue(), b"not a zip at all"):
        answer = scene.client.post(
            "/api/commissioning/check",
            files={"bundle": ("x.zip", content, "application/zip")},
            headers=CAROL,
        )
        assert answer.status_code == 422, answer.text
        message = answer.json()["message"]
        assert "record.json" in message
        assert "\n" not in message


def test_missing_record_node_and_body(scene: Scene) -> None:
    client = scene.client
    gone = client.post("/api/commissioning/check", json={"record_id": 9999}, headers=CAROL)
    assert (gone.status_code, gone.json()["error"]) == (404, "commissioning_not_found")
    off_bus = client.post(
        "/api/commissioning/check", json={"record_id": scene.record_id, "node": 42},
        headers=CAROL,
    )  # fmt: skip
    assert (off_bus.status_code, off_bus.json()["error"]) == (404, "node_not_found")
    unknown = client.post(
        "/api/commissioning/check", json={"record_id": 1, "nod": 2}, headers=CAROL
    )
    assert (unknown.status_code, unknown.json()["error"]) == (422, "invalid_request")
    assert required_role("POST", "/api/commissioning/check") is Role.VIEWER


def test_the_check_is_not_audited(scene: Scene) -> None:
    before = ok(scene.client.get("/api/audit", params={"node": 1}, headers=ALICE))
    by_record(scene)
    after = ok(scene.client.get("/api/audit", params={"node": 1}, headers=ALICE))
    assert [e["id"] for e in after] == [e["id"] for e in before]
