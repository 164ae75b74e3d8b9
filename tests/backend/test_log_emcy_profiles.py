"""EMCYs of nodes whose identity the log does not show: an MDi-S1-C's 2-byte alarm EMCY is
read as its alarm number (CiA 301's EMCY has 8 bytes), a node's drive can be named for a
decode (CLI --profile, API form field `profiles`), and the summary says when EMCYs fell back
to CiA 301."""

from __future__ import annotations

from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from servodesk.cli import main
from servodesk.logs import LogAnalysis
from servodesk.logs.context import parse_profiles

# node 1: an MDi-S1-C alarm 4 (位置超差); node 5: a CiA 301 EMCY 2310h of an unknown drive
LOG = (
    "(1700000000.000000) can0 701#05\n"
    "(1700000000.010000) can0 081#0400\n"
    "(1700000000.020000) can0 085#1023010000000000\n"
)


@pytest.fixture
def log(tmp_path: Path) -> Path:
    path = tmp_path / "no_identity.log"
    path.write_text(LOG)
    return path


def test_mdi_two_byte_alarm_without_identity(log: Path) -> None:
    analysis = LogAnalysis(log)
    emcys = [e for e in analysis.events() if e.kind == "emcy"]
    mdi = next(e for e in emcys if e.node == 1)
    assert "Error reset" not in mdi.text
    assert "alarm 4 位置超差 Position deviation too large" in mdi.text
    assert "(2-byte EMCY: MDi-S1-C CAN servo alarm number)" in mdi.text
    summary = "\n".join(analysis.summary())
    assert "reported a fault: alarm 4 位置超差" in summary
    assert "node 1: no identity in the log; its 2-byte EMCYs" in summary
    # node 5 sent a CiA 301 EMCY and nobody said which drive it is
    assert (
        "node 5: no identity in the log, EMCYs read as CiA 301; name its drive to decode"
        " vendor alarms" in summary
    )


def test_cli_profile_names_the_drive(log: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["decode-log", str(log), "--profile", "1=mdi-s1c", "--profile", "5=kinco"]) == 0
    summary = capsys.readouterr().out.split("\n\n", 1)[0]
    assert "node 1 (MDi-S1-C CAN servo) reported a fault: alarm 4 位置超差" in summary
    assert "node 5 (Kinco servo) reported a fault: 0x2310 I²t supervision released" in summary
    assert "no identity in the log" not in summary


def test_cli_unknown_profile_in_one_line(log: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["decode-log", str(log), "--profile", "1=mdi"]) == 1
    err = capsys.readouterr().err
    assert "--profile 'mdi': no such drive profile; known: mdi-s1c, kinco, cia402" in err


def test_parse_profiles() -> None:
    assert parse_profiles("1=mdi-s1c, 2=kinco") == {1: "mdi-s1c", 2: "kinco"}
    assert parse_profiles(["3=cia402"]) == {3: "cia402"}
    assert parse_profiles(None) == {}
    for bad in ("1", "0=kinco", "128=kinco", "x=kinco", "1="):
        with pytest.raises(ValueError, match="NODE=PROFILE"):
            parse_profiles(bad)


def test_api_profiles_field(client: TestClient) -> None:
    files = {"file": ("no_identity.log", LOG.encode(), "application/octet-stream")}
    body = client.post("/api/logs/decode", files=files, data={"profiles": "5=kinco"}).json()
    assert body["stats"]["profiles"] == {"5": "kinco"}
    node5 = next(e for e in body["events"] if e["kind"] == "emcy" and e["node"] == 5)
    assert node5["data"]["source"] == "vendor"
    refused = client.post("/api/logs/decode", files=files, data={"profiles": "5=acme"})
    assert refused.status_code == 422
    assert "no such drive profile" in refused.text
