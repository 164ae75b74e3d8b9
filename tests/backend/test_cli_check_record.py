"""`servodesk check-record` against simulated drives served over socketcand, as on a PC in the
field: the app (another process's role) makes the record and its bundle, the command needs
only the bundle and the bus."""

from __future__ import annotations

import uuid
from collections.abc import Iterator
from pathlib import Path

import can
import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.cli import main
from servodesk.settings import Settings
from servodesk_sim.runner import run_drives
from servodesk_sim.socketcand_server import SocketcandServer

PA_103 = "/api/nodes/1/params/PA-103"  # 2006:08 on the MDi-S1-C


@pytest.fixture
def served_port() -> Iterator[int]:
    bus = can.Bus(interface="virtual", channel=f"check-record-{uuid.uuid4().hex}")
    sim = run_drives(bus, [(1, "mdi-s1c")])
    server = SocketcandServer(sim, port=0)
    server.start()
    try:
        yield server.address[1]
    finally:
        server.stop()
        sim.stop()
        bus.shutdown()


def test_check_record_exit_codes_and_the_changed_line(
    served_port: int, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    options = {"host": "127.0.0.1", "port": served_port}
    settings = Settings(
        interface="socketcand", channel="can0", bus_options=options, data_dir=tmp_path / "app"
    )
    bundle = tmp_path / "bundle.zip"
    bus_flags = ["-i", "socketcand", "-c", "can0", "--bus-kwargs", "host=127.0.0.1",
                 f"port={served_port}"]  # fmt: skip
    with TestClient(create_app(settings, static_dir=None)) as client:
        record = client.post("/api/nodes/1/commissioning", json={"modes": ["pp"]}).json()
        assert client.put(PA_103, json={"value": 5000}).status_code == 200
        base = f"/api/commissioning/{record['id']}"
        assert client.post(f"{base}/steps/parameters/run").status_code == 200
        answer = client.get(f"{base}/report", params={"format": "zip"})
        assert answer.status_code == 200, answer.text
        bundle.write_bytes(answer.content)

        assert main(["check-record", str(bundle), *bus_flags]) == 0, capsys.readouterr()
        assert capsys.readouterr().out.splitlines()[-1] == "as handed over"

        assert client.put(PA_103, json={"value": 5500}).status_code == 200
        assert main(["check-record", str(bundle), "--node", "1", *bus_flags]) == 1
        out = capsys.readouterr().out
        # another PC: the bundle's audit log ends at hand-over, so who changed it is unknown
        assert "parameter 2006:08 PA-103: 5000 → 5500 (changed by: unknown)" in out
        assert out.splitlines()[-1] == "differs from hand-over"


def test_check_record_errors_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["check-record", str(tmp_path / "nowhere.zip"), "--sim"]) == 2
    assert "No such file" in capsys.readouterr().err
    junk = tmp_path / "junk.zip"
    junk.write_bytes(b"not a zip")
    assert main(["check-record", str(junk), "--sim"]) == 2
    err = capsys.readouterr().err
    assert "not a ServoDesk commissioning bundle" in err
    assert err.count("\n") == 1
