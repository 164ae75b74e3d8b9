"""LSS (CiA 305) and TIME frames decoded, and checked against Wireshark's CANopen dissector
(tshark) frame for frame: LSS command specifier, node-ID, mode, identity; TIME days and ms."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

from servodesk.logs import EventKind, LogAnalysis
from servodesk.logs.lss_time import time_of_day
from servodesk.logs.pcap import write_pcap
from tests.backend.log_session import write_log

TSHARK = shutil.which("tshark")
FIELDS = (
    "frame.number",
    "canopen.lss.cs",
    "canopen.lss.nid",
    "canopen.lss.switch.mode",
    "canopen.lss.addr.vendor",
    "canopen.lss.conf_id.err_code",
    "canopen.time_stamp_days",
    "canopen.time_stamp_ms",
)
T0 = 1_700_000_000.0
# 2026-11-27 05:51:21.123 UTC: day 15671 since 1984-01-01, 21 081 123 ms after midnight
TIME_DATA = (21_081_123).to_bytes(4, "little") + (15_671).to_bytes(2, "little")
FRAMES = [
    (0x7E5, bytes.fromhex("0401000000000000")),  # switch state global -> configuration
    (0x7E5, bytes.fromhex("4053564400000000")),  # switch state selective: vendor "DVS"
    (0x7E5, bytes.fromhex("1105000000000000")),  # configure node-ID 5
    (0x7E4, bytes.fromhex("1100000000000000")),  # ... done
    (0x7E5, bytes.fromhex("1300030000000000")),  # configure bit timing 250 kbit/s
    (0x7E5, bytes.fromhex("1700000000000000")),  # store configuration
    (0x7E4, bytes.fromhex("1701000000000000")),  # ... not supported
    (0x7E5, bytes.fromhex("5E00000000000000")),  # inquire node-ID
    (0x7E4, bytes.fromhex("5E05000000000000")),  # node-ID 5
    (0x7E5, bytes.fromhex("0400000000000000")),  # back to waiting
    (0x100, TIME_DATA),
]


def _frames() -> list[tuple[float, int, bytes]]:
    return [(T0 + i / 100, cob, data) for i, (cob, data) in enumerate(FRAMES)]


def _tshark(pcap: Path) -> dict[int, dict[str, int]]:
    assert TSHARK is not None, "tshark missing: run `make system-deps`"
    command = [TSHARK, "-r", str(pcap), "-d", "can.subdissector,canopen", "-T", "fields"]
    command += ["-E", "separator=\t", "-E", "occurrence=f"]
    for name in FIELDS:
        command += ["-e", name]
    out = subprocess.run(command, capture_output=True, text=True, check=True, timeout=60).stdout
    rows: dict[int, dict[str, int]] = {}
    for line in out.splitlines():
        values = dict(zip(FIELDS, line.split("\t"), strict=True))
        rows[int(values["frame.number"])] = {
            k.removeprefix("canopen."): int(v, 0) for k, v in values.items() if v
        }
    return rows


def test_lss_and_time_agree_with_tshark(tmp_path: Path) -> None:
    frames = _frames()
    log, pcap = tmp_path / "lss.log", tmp_path / "lss.pcap"
    write_log(frames, log)
    write_pcap(pcap, frames)
    theirs = _tshark(pcap)
    analysis = LogAnalysis(log, frames=True)
    events = list(analysis.events())
    decoded = {e.frame: e for e in events if e.kind in (EventKind.LSS, EventKind.TIME)}
    checked = 0
    for event in (e for e in events if e.kind == EventKind.FRAME):
        row = theirs[event.frame]
        text = decoded[event.frame].text
        if event.text == "LSS":
            assert row["lss.cs"] == event.code, f"frame {event.frame}"
            if "lss.nid" in row:
                assert f"node-ID {row['lss.nid']}" in text
            if "lss.switch.mode" in row:
                assert text.endswith(("waiting", "configuration")[row["lss.switch.mode"]])
            if "lss.addr.vendor" in row:
                assert f"vendor-ID {row['lss.addr.vendor']:08X}h" in text
        else:
            detail = json.loads(event.data or "{}")
            assert (detail["days"], detail["ms"]) == (
                row["time_stamp_days"],
                row["time_stamp_ms"],
            )
        checked += 1
    assert checked == len(FRAMES)
    fields = {k for row in theirs.values() for k in row}
    assert {"lss.nid", "lss.switch.mode", "lss.addr.vendor", "time_stamp_ms"} <= fields
    assert [decoded[n].text for n in sorted(decoded)] == [
        "LSS master: switch state global → configuration",
        "LSS master: switch state selective, vendor-ID 00445653h",
        "LSS master: configure node-ID 5",
        "LSS slave: configure node-ID: done",
        "LSS master: configure bit timing 250 kbit/s",
        "LSS master: store configuration",
        "LSS slave: store: store configuration not supported",
        "LSS master: inquire node-ID",
        "LSS slave: node-ID 5",
        "LSS master: switch state global → waiting",
        "TIME 2026-11-27 05:51:21.123 (day 15671 since 1984-01-01)",
    ]
    summary = "\n".join(analysis.summary())
    assert "LSS master: configure node-ID 5" in summary
    assert analysis.stats()["counts"] == {"lss": 10, "time": 1}


def test_time_of_day_reserved_bits_and_length() -> None:
    stamp = time_of_day(bytes.fromhex("FFFFFFFF0000"))
    assert stamp is not None
    assert stamp.ms == 0x0FFFFFFF  # the top 4 bits are reserved
    assert time_of_day(b"\x00" * 4) is None
