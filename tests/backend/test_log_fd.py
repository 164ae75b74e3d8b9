"""CAN FD frames in a log: counted and named, never the end of the decode (a candump `##`
line, and ASC/BLF files with FD frames written by python-can's own writers)."""

from __future__ import annotations

from pathlib import Path

import can
import pytest

from servodesk.cli import main
from servodesk.logs import LogAnalysis

FD_LINE = "FD frame(s) (more than 8 data bytes) counted, not decoded as CANopen"


def test_candump_fd_line_is_counted_not_fatal(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    log = tmp_path / "fd.log"
    log.write_text(
        "(1700000000.000000) can0 701#05\n"
        "(1700000000.100000) can0 181##1112233445566778899AABBCC\n"
        "(1700000000.200000) can0 581#4B41600037020000\n"
    )
    assert main(["decode-log", str(log)]) == 0
    out = capsys.readouterr().out
    summary, events = out.split("\n\n", 1)
    assert f"1 CAN {FD_LINE}" in summary
    # the classic frames around it are decoded as usual
    assert "SDO read 6041:00 Statusword = 0x0237" in events
    assert "node 1 went to Operation enabled" in events


def _fd_messages() -> list[can.Message]:
    return [
        can.Message(timestamp=1.0, arbitration_id=0x701, data=b"\x05", is_extended_id=False),
        can.Message(
            timestamp=1.1,
            arbitration_id=0x181,
            data=bytes(range(12)),
            is_extended_id=False,
            is_fd=True,
            bitrate_switch=True,
        ),
        can.Message(
            timestamp=1.2,
            arbitration_id=0x581,
            data=bytes.fromhex("4B41600037020000"),
            is_extended_id=False,
        ),
        can.Message(timestamp=1.3, arbitration_id=0x12345, data=bytes(64), is_fd=True),
    ]


@pytest.mark.parametrize("suffix", [".asc", ".blf"])
def test_fd_frames_in_vector_logs(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"fd{suffix}"
    with can.Logger(path) as writer:  # python-can's own ASC/BLF writers
        for message in _fd_messages():
            writer.on_message_received(message)
    analysis = LogAnalysis(path)
    texts = [e.text for e in analysis.events()]
    assert "node 1 SDO read 6041:00 Statusword = 0x0237 (567) [Operation enabled]" in texts
    stats = analysis.stats()
    assert stats["frames"] == 4
    assert stats["counts"]["fd"] == 2
    assert f"2 CAN {FD_LINE} and not in the bus load." in analysis.summary()
    # only the classic frames load the bus: 1-byte + 8-byte frames, worst-case stuffing
    assert stats["bus_load_peak_percent"] == pytest.approx(100 * (65 + 135) / 500_000, abs=0.01)


def test_only_fd_frames(tmp_path: Path) -> None:
    log = tmp_path / "fd_only.log"
    log.write_text("(1700000000.000000) can0 181##0" + "11" * 64 + "\n")
    analysis = LogAnalysis(log)
    list(analysis.events())
    summary = analysis.summary()
    assert "Bus load: no classic CAN frames to count." in summary
    assert f"1 CAN {FD_LINE} and not in the bus load." in summary
