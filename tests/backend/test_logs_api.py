"""Log upload, paging and export through the API, and recording the live bus to a file that
python-can reads back (then decoding that recording)."""

from __future__ import annotations

import io
import json
from pathlib import Path

import can
import pyarrow.parquet as pq
import pytest
from fastapi.testclient import TestClient


def candump(tmp_path: Path) -> bytes:
    path = tmp_path / "session.log"
    frames = [
        (0x701, b"\x00"),  # node 1 boot-up
        (0x081, b"\x04\x00"),  # MDi alarm 4 (no identity read: known by its 2-byte shape)
        (0x703, b"\x00"),
        (0x083, bytes([0x11, 0x86, 0x21, 0, 0, 0, 0, 0])),  # following error
    ] * 5
    with can.Logger(path) as writer:
        for i, (can_id, data) in enumerate(frames):
            writer.on_message_received(
                can.Message(
                    timestamp=1000.0 + i / 100,
                    arbitration_id=can_id,
                    data=data,
                    is_extended_id=False,
                )
            )
    return path.read_bytes()


def test_upload_page_and_export(client: TestClient, tmp_path: Path) -> None:
    files = {"file": ("session.log", candump(tmp_path), "application/octet-stream")}
    decoded = client.post("/api/logs/decode", files=files)
    assert decoded.status_code == 200, decoded.text
    body = decoded.json()
    assert body["summary"]
    assert body["stats"]
    kinds = [e["kind"] for e in body["events"]]
    assert kinds.count("emcy") == 10
    assert kinds.count("boot-up") == 10
    assert body["next"] is None
    emcy = next(e for e in body["events"] if e["kind"] == "emcy" and e["node"] == 3)
    assert emcy["data"]["name_en"] == "Following error"
    alarm = next(e for e in body["events"] if e["kind"] == "emcy" and e["node"] == 1)
    assert alarm["data"]["name_en"] == "Position deviation too large"
    log_id = body["id"]
    first = client.get(f"/api/logs/{log_id}/events?limit=3").json()
    assert [e["seq"] for e in first["events"]] == [0, 1, 2]
    second = client.get(f"/api/logs/{log_id}/events?since={first['next']}&limit=3").json()
    assert second["events"][0]["seq"] == 3
    total = len(body["events"])
    csv = client.get(f"/api/logs/{log_id}/export?format=csv")
    assert csv.status_code == 200
    assert csv.headers["content-type"].startswith("text/csv")
    assert len(csv.text.strip().splitlines()) == total + 1  # header
    lines = client.get(f"/api/logs/{log_id}/export?format=json").text.strip().splitlines()
    assert [json.loads(line)["seq"] for line in lines] == list(range(total))
    parquet = client.get(f"/api/logs/{log_id}/export?format=parquet")
    assert pq.read_table(io.BytesIO(parquet.content)).num_rows == total


def test_unknown_log_and_unreadable_file_are_refused(client: TestClient) -> None:
    missing = client.get(f"/api/logs/{'0' * 32}/events")
    assert missing.status_code == 404
    assert missing.json()["error"] == "log_not_found"
    assert client.get("/api/logs/..%2Fx/export").status_code == 404
    bad = client.post("/api/logs/decode", files={"file": ("x.blf", b"not a blf", "text/plain")})
    assert bad.status_code == 422
    assert bad.json()["error"] == "invalid_value"
    other = client.post("/api/logs/decode", files={"file": ("notes.txt", b"hi", "text/plain")})
    assert other.status_code == 422


@pytest.mark.parametrize("fmt", ["blf", "asc", "log", "mf4"])
def test_recording_makes_a_file_python_can_reads(
    client: TestClient, tmp_path: Path, fmt: str
) -> None:
    assert client.get("/api/recording").json()["active"] is False
    started = client.post("/api/recording", json={"format": fmt}).json()
    assert started["active"]
    assert started["format"] == fmt
    for _ in range(5):
        assert client.get("/api/nodes/1/sdo/1000/0").status_code == 200  # answers on 581h
    stopped = client.delete("/api/recording")
    assert stopped.status_code == 200
    path = tmp_path / f"rec.{fmt}"
    path.write_bytes(stopped.content)
    frames = list(can.LogReader(path))
    assert sum(1 for m in frames if m.arbitration_id == 0x581) >= 5
    # the whole bus: the tool's own requests on 601h are in the file too, before their answers
    requests = [m for m in frames if m.arbitration_id == 0x601]
    assert len(requests) >= 5
    first_answer = next(m for m in frames if m.arbitration_id == 0x581)
    assert requests[0].timestamp <= first_answer.timestamp
    again = client.delete("/api/recording")
    assert again.status_code == 409
    assert again.json()["error"] == "recording_not_running"
    decoded = client.post("/api/logs/decode", files={"file": (path.name, path.read_bytes())})
    assert decoded.status_code == 200
    assert any(e["kind"] == "sdo" for e in decoded.json()["events"])
