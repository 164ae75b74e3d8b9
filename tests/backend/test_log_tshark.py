"""An independent check: the recorded session as a SocketCAN pcap, decoded by Wireshark's
CANopen dissector (tshark), must agree frame for frame with our decoder on NMT command/node,
heartbeat state, SDO command specifier/index/sub-index/abort code and EMCY code/register."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

from servodesk.logs import EventKind, LogAnalysis
from servodesk.logs.pcap import TSHARK_FIELDS, tshark_command, write_pcap
from tests.backend.log_session import record, write_log

TSHARK = shutil.which("tshark")
Row = dict[str, int]


def tshark_rows(pcap: Path) -> dict[int, Row]:
    # `make test` installs it (system-deps): a missing decoder fails, it does not skip
    assert TSHARK is not None, "tshark missing: run `make system-deps`"
    out = subprocess.run(
        tshark_command(TSHARK, pcap), capture_output=True, text=True, check=True, timeout=60
    ).stdout
    rows: dict[int, Row] = {}
    for line in out.splitlines():
        values = dict(zip(TSHARK_FIELDS, line.split("\t"), strict=True))
        rows[int(values["frame.number"])] = {
            k.removeprefix("canopen."): int(v, 0) for k, v in values.items() if v
        }
    return rows


def test_tshark_agrees_frame_for_frame(tmp_path: Path) -> None:
    frames = record()
    log = tmp_path / "session.log"
    write_log(frames, log)
    pcap = tmp_path / "session.pcap"
    write_pcap(pcap, frames)
    theirs = tshark_rows(pcap)
    assert len(theirs) == len(frames)

    analysis = LogAnalysis(log, frames=True)
    events = list(analysis.events())
    ours = [e for e in events if e.kind == EventKind.FRAME]
    aborts = {e.frame: e for e in events if e.kind == EventKind.SDO_ABORT}
    assert ours, "no frames decoded"
    checked = {"nmt": 0, "heartbeat": 0, "sdo": 0, "sdo index": 0, "abort": 0, "emcy": 0}
    for event in ours:
        row = theirs[event.frame]
        if event.text == "NMT":
            assert (row["nmt_ctrl.cd"], row["nmt_ctrl.node_id"]) == (event.code, event.node or 0)
            checked["nmt"] += 1
        elif event.text == "heartbeat":
            assert row["nmt_guard.state"] == event.code
            checked["heartbeat"] += 1
        elif event.text.startswith("SDO"):
            side = "sdo.ccs" if event.text == "SDO request" else "sdo.scs"
            assert row[side] == event.code, f"frame {event.frame}"
            checked["sdo"] += 1
            if "sdo.main_idx" in row:  # initiate and abort frames name the object
                assert (row["sdo.main_idx"], row["sdo.sub_idx"]) == (event.index, event.subindex)
                checked["sdo index"] += 1
            if "sdo.abort_code" in row:
                assert aborts[event.frame].code == row["sdo.abort_code"]
                checked["abort"] += 1
        elif event.text == "EMCY":
            assert row["em.err_code"] == event.code
            register = json.loads(event.data or "{}")["error_register"]
            if register is not None:  # only the CiA 301 format carries 1001h
                assert row["em.err_reg"] == register
            checked["emcy"] += 1
    # every kind of frame was compared, and every frame tshark decoded as NMT/SDO/EMCY is ours
    assert checked == {"nmt": 2, "heartbeat": checked["heartbeat"], "sdo": checked["sdo"],
                       "sdo index": checked["sdo index"], "abort": 1, "emcy": 4}  # fmt: skip
    assert checked["heartbeat"] > 20
    assert checked["sdo index"] > 20
    canopen = {n for n, r in theirs.items() if {"nmt_ctrl.cd", "sdo.ccs", "sdo.scs",
                                                 "em.err_code"} & r.keys()}  # fmt: skip
    assert canopen == {e.frame for e in ours if e.text != "heartbeat"}
