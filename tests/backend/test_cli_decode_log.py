"""`servodesk decode-log`: summary first, every export format, one-line errors."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import pyarrow.parquet as pq
import pytest

from servodesk.cli import main
from tests.backend.log_session import record, write_log


@pytest.fixture(scope="module")
def log(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("logs") / "session.log"
    write_log(record(), path)
    return path


def _err_lines(err: str) -> list[str]:
    # the progress bar redraws with \r; the messages are whole lines
    return [line for line in err.replace("\r", "\n").splitlines() if line.startswith("servodesk")]


def test_text_summary_first(log: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["decode-log", str(log)]) == 0
    out = capsys.readouterr().out
    summary, events = out.split("\n\n", 1)
    assert summary.splitlines()[0].startswith("159 frames over 1.2")
    assert "reported a fault: alarm 4 位置超差" in summary
    assert "boot-up" in events.splitlines()[0]
    assert "SDO read 1008:00 Manufacturer device name = DVS_CANOPEN" in events


def test_json_lines(log: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["decode-log", str(log), "--format", "json"]) == 0
    lines = capsys.readouterr().out.splitlines()
    head = json.loads(lines[0])
    assert head["stats"]["frames"] == 159
    assert head["summary"]
    events = [json.loads(line) for line in lines[1:]]
    assert [e["seq"] for e in events] == list(range(len(events)))
    assert {"emcy", "sdo", "sdo-abort", "boot-up", "nmt"} <= {e["kind"] for e in events}


def test_csv_to_a_file(log: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "events.csv"
    assert main(["decode-log", str(log), "--format", "csv", "-o", str(out)]) == 0
    assert capsys.readouterr().out.startswith("159 frames")  # the summary on stdout
    rows = list(csv.DictReader(io.StringIO(out.read_text(encoding="utf-8"))))
    emcy = [r for r in rows if r["kind"] == "emcy"]
    assert [r["code"] for r in emcy] == ["4", "34321", "34321", "0"]


def test_parquet(log: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "events.parquet"
    assert main(["decode-log", str(log), "--format", "parquet", "-o", str(out)]) == 0
    table = pq.read_table(out)
    assert table.column_names[:4] == ["seq", "time", "frame", "kind"]
    assert table.num_rows == len(table.column("seq").to_pylist()) > 30


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["decode-log", "/nonexistent/x.log"], "servodesk: /nonexistent/x.log: no such file"),
        (["decode-log", "{log}", "--format", "parquet"],
         "servodesk: --format parquet writes a file: give it with -o OUT"),
        (["decode-log", "{bad}"], "servodesk: bad.xyz: unknown log format '.xyz'; use one of"),
        (["decode-log", "{garbled}"], "servodesk: {garbled}: cannot read the log:"),
    ],
)  # fmt: skip
def test_one_line_errors(
    argv: list[str], message: str, log: Path, tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:  # fmt: skip
    bad = tmp_path / "bad.xyz"
    bad.write_text("x")
    garbled = tmp_path / "garbled.log"
    garbled.write_text("(1700000000.000000) can0 not-a-frame\n")
    names = {"log": str(log), "bad": str(bad), "garbled": str(garbled)}
    assert main([a.format(**names) for a in argv]) == 1
    lines = _err_lines(capsys.readouterr().err)
    assert len(lines) == 1
    assert lines[0].startswith(message.format(**names))
