"""SDO transfers reassembled from exact frames (CiA 301 §7.2.4.3), one channel at a time."""

from __future__ import annotations

import pytest

from servodesk.logs.sdo import KEEP_BYTES, SdoChannel, SdoMode, SdoTransfer

REQ, RSP = "req", "rsp"
Script = list[tuple[str, str]]


def run(script: Script) -> list[SdoTransfer]:
    channel = SdoChannel()
    done: list[SdoTransfer] = []
    for number, (side, hex_data) in enumerate(script, start=1):
        feed = channel.request if side == REQ else channel.response
        result = feed(bytes.fromhex(hex_data), float(number), number)
        if result is not None:
            done.append(result)
    return done


CASES: list[tuple[str, Script, SdoTransfer]] = [
    (
        "expedited upload",
        [(REQ, "40 41 60 00 00 00 00 00"), (RSP, "4B 41 60 00 37 02 00 00")],
        SdoTransfer(True, 0x6041, 0, SdoMode.EXPEDITED, 2, b"\x37\x02", start=1.0, first_frame=1),
    ),
    (
        "expedited download",
        [(REQ, "2B 40 60 00 0F 00 00 00"), (RSP, "60 40 60 00 00 00 00 00")],
        SdoTransfer(False, 0x6040, 0, SdoMode.EXPEDITED, 2, b"\x0f\x00", start=1.0, first_frame=1),
    ),
    (
        "segmented upload of 1008h",
        [
            (REQ, "40 08 10 00 00 00 00 00"),
            (RSP, "41 08 10 00 0B 00 00 00"),  # size indicated: 11
            (REQ, "60 00 00 00 00 00 00 00"),
            (RSP, "00 44 56 53 5F 43 41 4E"),  # "DVS_CAN", toggle 0
            (REQ, "70 00 00 00 00 00 00 00"),
            (RSP, "17 4F 50 45 4E 00 00 00"),  # toggle 1, 3 unused, last: "OPEN"
        ],
        SdoTransfer(True, 0x1008, 0, SdoMode.SEGMENTED, 11, b"DVS_CANOPEN", start=1.0,
                    first_frame=1),
    ),
    (
        "segmented download",
        [
            (REQ, "21 81 60 00 04 00 00 00"),
            (RSP, "60 81 60 00 00 00 00 00"),
            (REQ, "07 E8 03 00 00 00 00 00"),  # 3 unused, last
            (RSP, "20 00 00 00 00 00 00 00"),
        ],
        SdoTransfer(False, 0x6081, 0, SdoMode.SEGMENTED, 4, bytes.fromhex("E8 03 00 00"),
                    start=1.0, first_frame=1),
    ),
    (
        "abort by the server",
        [(REQ, "2B 5A 60 00 03 00 00 00"), (RSP, "80 5A 60 00 30 00 09 06")],
        SdoTransfer(False, 0x605A, 0, SdoMode.EXPEDITED, 2, b"\x03\x00", abort=0x06090030,
                    start=1.0, first_frame=1),
    ),
    (
        "abort by the client during a segmented upload",
        [
            (REQ, "40 08 10 00 00 00 00 00"),
            (RSP, "41 08 10 00 0B 00 00 00"),
            (REQ, "80 08 10 00 00 00 04 05"),
        ],
        SdoTransfer(True, 0x1008, 0, SdoMode.SEGMENTED, 0, b"", abort=0x05040000,
                    aborted_by_client=True, start=1.0, first_frame=1),
    ),
    (
        "block download of 10 bytes",
        [
            (REQ, "C6 00 20 01 0A 00 00 00"),  # CRC, size indicated 10
            (RSP, "A4 00 20 01 7F 00 00 00"),  # blksize 127
            (REQ, "01 30 31 32 33 34 35 36"),  # seq 1
            (REQ, "82 37 38 39 00 00 00 00"),  # seq 2, last
            (RSP, "A2 02 7F 00 00 00 00 00"),  # ack seq 2
            (REQ, "D1 12 34 00 00 00 00 00"),  # end: 4 unused bytes in the last segment
            (RSP, "A1 00 00 00 00 00 00 00"),
        ],
        SdoTransfer(False, 0x2000, 1, SdoMode.BLOCK, 10, b"0123456789", start=1.0,
                    first_frame=1),
    ),
    (
        "block upload of 9 bytes",
        [
            (REQ, "A4 08 10 00 7F 00 00 00"),  # blksize 127, pst 0
            (RSP, "C6 08 10 00 09 00 00 00"),  # size 9
            (REQ, "A3 00 00 00 00 00 00 00"),  # start
            (RSP, "01 43 35 2D 45 2D 53 49"),
            (RSP, "82 4D 00 00 00 00 00 00"),
            (REQ, "A2 02 7F 00 00 00 00 00"),  # ack
            (RSP, "D5 00 00 00 00 00 00 00"),  # end: 5 unused
            (REQ, "A1 00 00 00 00 00 00 00"),
        ],
        SdoTransfer(True, 0x1008, 0, SdoMode.BLOCK, 9, b"C5-E-SIM\x00", start=1.0,
                    first_frame=1),
    ),
]  # fmt: skip


@pytest.mark.parametrize(("name", "script", "expected"), CASES, ids=[c[0] for c in CASES])
def test_transfers(name: str, script: Script, expected: SdoTransfer) -> None:
    assert run(script) == [expected]


def test_command_specifier_and_object_per_frame() -> None:
    channel = SdoChannel()
    channel.request(bytes.fromhex("40 08 10 00 00 00 00 00"), 0.0, 1)
    assert (channel.cs, channel.index, channel.subindex) == (2, 0x1008, 0)
    channel.response(bytes.fromhex("41 08 10 00 0B 00 00 00"), 0.0, 2)
    assert channel.cs == 2
    assert channel.busy
    channel.request(bytes.fromhex("60 00 00 00 00 00 00 00"), 0.0, 3)
    assert (channel.cs, channel.index) == (3, 0x1008)  # a segment keeps the transfer's object


def test_a_new_initiate_interrupts_an_open_transfer() -> None:
    done = run([(REQ, "40 08 10 00 00 00 00 00"), (RSP, "41 08 10 00 0B 00 00 00"),
                (REQ, "40 41 60 00 00 00 00 00"), (RSP, "4B 41 60 00 37 02 00 00")])  # fmt: skip
    assert [d.error for d in done] == ["incomplete: a new transfer started first", None]
    assert [d.index for d in done] == [0x1008, 0x6041]


def test_lone_frames_from_before_the_log_are_ignored_or_kept() -> None:
    # a segment response with no transfer open: nothing; an expedited upload response alone
    # still names its object and value
    done = run([(RSP, "00 44 56 53 5F 43 41 4E"), (RSP, "43 18 10 01 53 56 44 00")])
    assert [(d.index, d.subindex, d.data) for d in done] == [(0x1018, 1, b"SVD\x00")]


def test_flush_at_the_end_of_the_log() -> None:
    channel = SdoChannel()
    channel.request(bytes.fromhex("40 08 10 00 00 00 00 00"), 0.0, 1)
    flushed = channel.flush()
    assert flushed is not None
    assert flushed.error == "incomplete: the log ends during the transfer"
    assert channel.flush() is None


def test_data_kept_is_bounded() -> None:
    script: Script = [(REQ, "40 00 30 00 00 00 00 00"), (RSP, "41 00 30 00 E8 03 00 00")]
    for n in range(143):  # 1000 bytes in 7-byte segments
        last = 0x01 if n == 142 else 0
        script.append((REQ, f"{0x60 | (n & 1) << 4:02X} 00 00 00 00 00 00 00"))
        script.append((RSP, f"{(n & 1) << 4 | last:02X} 11 22 33 44 55 66 77"))
    (done,) = run(script)
    assert done.size == 1001
    assert len(done.data) == KEEP_BYTES
