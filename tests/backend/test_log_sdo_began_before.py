"""An SDO abort whose transfer began before the log starts: the log does not say whether it was
a read or a write, so the timeline says "SDO transfer (began before the log)" unless the abort
code itself tells (06010002h: a write of a read-only object)."""

from __future__ import annotations

from pathlib import Path

import pytest

from servodesk.logs import EventKind, LogAnalysis


def _abort_text(tmp_path: Path, line: str) -> str:
    log = tmp_path / "mid.log"
    log.write_text(f"(1700000000.000000) can0 {line}\n")
    analysis = LogAnalysis(log)
    (abort,) = [e for e in analysis.events() if e.kind == EventKind.SDO_ABORT]
    assert abort.text in "\n".join(analysis.summary())
    return abort.text


@pytest.mark.parametrize(
    ("line", "expected"),
    [
        (  # the state refuses the controlword: a read or a write alike
            "581#8040600022000008",
            "node 1 SDO transfer (began before the log) 6040:00 Controlword aborted by the"
            " drive: 08000022h",
        ),
        (
            "581#8000100002000106",
            "node 1 SDO write (began before the log) 1000:00 Device type aborted by the"
            " drive: 06010002h",
        ),
        (
            "601#8008100000000405",
            "node 1 SDO transfer (began before the log) 1008:00 Manufacturer device name"
            " aborted by the master: 05040000h",
        ),
    ],
)
def test_abort_of_a_transfer_before_the_log(tmp_path: Path, line: str, expected: str) -> None:
    assert _abort_text(tmp_path, line).startswith(expected)


def test_abort_of_a_transfer_in_the_log_keeps_its_direction(tmp_path: Path) -> None:
    log = tmp_path / "whole.log"
    log.write_text(
        "(1700000000.000000) can0 601#4040600000000000\n"
        "(1700000000.001000) can0 581#8040600022000008\n"
    )
    (abort,) = [e for e in LogAnalysis(log).events() if e.kind == EventKind.SDO_ABORT]
    assert abort.text.startswith("node 1 SDO read 6040:00 Controlword aborted by the drive")
