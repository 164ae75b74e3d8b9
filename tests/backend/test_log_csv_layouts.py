"""CSV logs of other tools: SavvyCAN's GVRET CSV is read; a layout that is not read is refused
in one line that names the layouts that are (not python-can's bare "too many values to
unpack"); a BusMaster .log says which .log layout is read."""

from __future__ import annotations

from pathlib import Path

import can
import pytest

from servodesk.cli import main
from servodesk.logs import LogAnalysis

SAVVYCAN = (
    "Time Stamp,ID,Extended,Dir,Bus,LEN,D1,D2,D3,D4,D5,D6,D7,D8\n"
    "1000000,00000701,false,Rx,0,1,05,\n"
    "1010000,0x00000581,false,Rx,0,8,4B,41,60,00,37,02,00,00,\n"
    "1020000,00000085,false,Rx,0,8,10,23,01,00,00,00,00,00,\n"
    "1030000,18FF50E5,true,Rx,0,2,01,02,\n"
)


def _errors(err: str) -> list[str]:
    return [line for line in err.replace("\r", "\n").splitlines() if line.startswith("servodesk")]


@pytest.mark.parametrize("header", [True, False])
def test_savvycan_csv_is_read(tmp_path: Path, header: bool) -> None:
    text = SAVVYCAN
    if not header:  # SavvyCAN's older layout: no Dir column
        text = "\n".join(
            ",".join(c for i, c in enumerate(line.split(",")) if i != 3)
            for line in SAVVYCAN.splitlines()
        )
    path = tmp_path / "savvy.csv"
    path.write_text(text)
    analysis = LogAnalysis(path)
    texts = [e.text for e in analysis.events()]
    assert "node 1 NMT state Operational" in texts
    assert "node 1 SDO read 6041:00 Statusword = 0x0237 (567) [Operation enabled]" in texts
    assert "node 5 EMCY: 0x2310 Continuous over-current" in texts
    stats = analysis.stats()
    assert stats["frames"] == 4
    assert stats["counts"]["extended"] == 1
    assert stats["start"] == pytest.approx(1.0)


def test_other_csv_layout_refused_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "busmaster.csv"
    path.write_text("Time,Tx/Rx,Channel,CAN ID,Type,DLC,Data\n05:51:21:1230,Rx,1,0x701,s,1,05\n")
    assert main(["decode-log", str(path)]) == 1
    (line,) = _errors(capsys.readouterr().err)
    assert "too many values" not in line
    assert "a CSV layout this tool does not read (header 'Time,Tx/Rx,Channel," in line
    assert "python-can's CSV (timestamp,arbitration_id,extended,remote,error,dlc,data)" in line
    assert "SavvyCAN's (Time Stamp,ID,Extended,Dir,Bus,LEN,D1,...,D8)" in line


def test_python_can_csv_still_read(tmp_path: Path) -> None:
    path = tmp_path / "pc.csv"
    with can.Logger(path) as writer:
        writer.on_message_received(
            can.Message(timestamp=5.0, arbitration_id=0x701, data=b"\x7f", is_extended_id=False)
        )
    texts = [e.text for e in LogAnalysis(path).events()]
    assert "node 1 NMT state Pre-operational" in texts


def test_busmaster_log_names_the_layout(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "bm.log"
    path.write_text("***BUSMASTER Ver 3.2.2***\n***PROTOCOL CAN***\n")
    assert main(["decode-log", str(path)]) == 1
    (line,) = _errors(capsys.readouterr().err)
    assert "line 1 is not a candump frame" in line
    assert "(a .log is read as candump -l: '(1700000000.000000) can0 181#0102')" in line


def test_unreadable_trc_names_the_layout(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "cba.trc"
    path.write_text(";$FILEVERSION=9.9\n   1)  0.0  Rx  0701  1  05\n")
    assert main(["decode-log", str(path)]) == 1
    (line,) = _errors(capsys.readouterr().err)
    assert "(expected PEAK's TRC (PCAN-View, file versions 1.0 to 2.1))" in line
