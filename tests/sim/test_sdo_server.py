"""SdoServer: exact request/answer payloads from the manuals, segmented and block transfers,
timeouts, and a round trip with python-canopen's own SDO client over a virtual bus."""

from __future__ import annotations

import threading
from collections.abc import Iterator
from typing import Any

import can
import canopen
import pytest
from canopen.objectdictionary import ObjectDictionary, ODRecord, ODVariable
from canopen.objectdictionary import datatypes as dt

from servodesk_sim.od_store import LengthCheck, ObjectStore, Value
from servodesk_sim.sdo_server import SdoServer, crc16

NODE = 4


def _var(index: int, sub: int, data_type: int, access: str, default: Value) -> ODVariable:
    var = ODVariable(f"obj_{index:04X}_{sub:02X}", index, sub)
    var.data_type = data_type
    var.access_type = access
    # canopen annotates `default` as int, but its EDS import stores str/bytes there too.
    untyped: Any = var
    untyped.default = default
    return var


def make_od() -> ObjectDictionary:
    od = canopen.import_od(None)  # an empty dictionary, filled in below
    od.add_object(_var(0x1000, 0, dt.UNSIGNED32, "ro", 0x00020192))  # Device type
    od.add_object(_var(0x1001, 0, dt.UNSIGNED8, "ro", 0))  # Error register
    od.add_object(_var(0x1008, 0, dt.VISIBLE_STRING, "const", "DVS_CANOPEN"))  # Device name
    record = ODRecord("obj_2006", 0x2006)
    record.add_member(_var(0x2006, 0, dt.UNSIGNED8, "ro", 8))
    record.add_member(_var(0x2006, 8, dt.UNSIGNED16, "rw", 6000))  # max speed, MDi-S1-C manual P-08
    od.add_object(record)
    od.add_object(_var(0x2007, 0, dt.UNSIGNED24, "rw", 0x123456))
    od.add_object(_var(0x2008, 0, dt.VISIBLE_STRING, "rw", ""))
    od.add_object(_var(0x2200, 0, dt.DOMAIN, "rw", b""))
    od.add_object(_var(0x6040, 0, dt.UNSIGNED16, "rw", 0))  # Controlword
    od.add_object(_var(0x6041, 0, dt.UNSIGNED16, "ro", 0x0240))  # Statusword
    od.add_object(_var(0x6060, 0, dt.INTEGER8, "rw", 0))  # Modes of operation
    od.add_object(_var(0x607A, 0, dt.INTEGER32, "rw", 0))  # Target position
    od.add_object(_var(0x60FF, 0, dt.INTEGER32, "rw", 0))  # Target velocity
    return od


def make(
    length_check: LengthCheck = LengthCheck.GENERIC, *, block: bool = False
) -> tuple[SdoServer, ObjectStore]:
    store = ObjectStore(make_od(), NODE, length_check=length_check)
    return SdoServer(store, block_transfer=block), store


def h(text: str) -> bytes:
    return bytes.fromhex(text)


def ask(server: SdoServer, request: str, now: float = 0.0) -> list[str]:
    """Send one request; the answers as upper-case hex strings like the manuals print them."""
    return [reply.hex(" ").upper() for reply in server.on_request(h(request), now)]


# ---------------------------------------------------------------------------- manual examples


def test_mdi_manual_expedited_write_of_target_velocity() -> None:
    server, store = make()
    # MDi-S1-C manual tables 2.16 / 2.17: write 1000 to 60FFh on node 4
    assert ask(server, "23 FF 60 00 E8 03 00 00") == ["60 FF 60 00 00 00 00 00"]
    assert store.get(0x60FF) == 1000


@pytest.mark.parametrize(
    ("length_check", "request_", "answer"),
    [
        # MDi-S1-C manual table 2.18: size mismatch on INTEGER32 60FFh -> 06070010
        (LengthCheck.GENERIC, "2B FF 60 00 E8 03 00 00", "80 FF 60 00 10 00 07 06"),
        (LengthCheck.GENERIC, "2F FF 60 00 E8 00 00 00", "80 FF 60 00 10 00 07 06"),
        (LengthCheck.GENERIC, "23 40 60 00 0F 00 00 00", "80 40 60 00 10 00 07 06"),
        # Nanotec article error list: too short -> 06070013, too long -> 06070012
        (LengthCheck.SPECIFIC, "2B FF 60 00 E8 03 00 00", "80 FF 60 00 13 00 07 06"),
        (LengthCheck.SPECIFIC, "2F FF 60 00 E8 00 00 00", "80 FF 60 00 13 00 07 06"),
        (LengthCheck.SPECIFIC, "23 40 60 00 0F 00 00 00", "80 40 60 00 12 00 07 06"),
    ],
)
def test_expedited_write_with_wrong_size(
    length_check: LengthCheck, request_: str, answer: str
) -> None:
    server, store = make(length_check)
    assert ask(server, request_) == [answer]
    assert (store.get(0x60FF), store.get(0x6040)) == (0, 0)


def test_mdi_manual_expedited_read_of_max_speed() -> None:
    server, _ = make()
    # MDi-S1-C manual tables 2.30 / 2.31: 2006h:08 = 6000 rpm = 1770h
    assert ask(server, "40 06 20 08 00 00 00 00") == ["4B 06 20 08 70 17 00 00"]


@pytest.mark.parametrize(
    ("block", "request_"),
    [
        (False, "A0 06 20 08 7F 00 00 00"),  # block upload on a drive without block transfer
        (False, "A4 06 20 08 7F 00 00 00"),
        (False, "C6 06 20 08 02 00 00 00"),  # block download
        (False, "E0 06 20 08 00 00 00 00"),  # ccs 7: no such command
        (True, "E0 06 20 08 00 00 00 00"),
        (True, "FF 06 20 08 00 00 00 00"),
    ],
)
def test_mdi_manual_unknown_command_aborts_05040001(block: bool, request_: str) -> None:
    server, _ = make(block=block)
    # MDi-S1-C manual table 2.32
    assert ask(server, request_) == ["80 06 20 08 01 00 04 05"]


def test_mdi_manual_segmented_read_of_device_name() -> None:
    server, _ = make()
    # MDi-S1-C manual table 2.33: 41h + size 11
    assert ask(server, "40 08 10 00 00 00 00 00") == ["41 08 10 00 0B 00 00 00"]
    # table 2.34: toggle 0 -> 00h + 7 bytes "DVS_CAN"
    assert ask(server, "60 00 00 00 00 00 00 00") == ["00 44 56 53 5F 43 41 4E"]
    # table 2.35: toggle 1, 4 bytes "OPEN": n = 3 unused, c = 1 -> 10h | 3 << 1 | 1 = 17h
    assert ask(server, "70 00 00 00 00 00 00 00") == ["17 4F 50 45 4E 00 00 00"]
    # the transfer is over: another segment request is out of place
    assert ask(server, "60 00 00 00 00 00 00 00") == ["80 00 00 00 01 00 04 05"]


def test_kinco_manual_read_statusword() -> None:
    server, _ = make()
    assert ask(server, "40 41 60 00 00 00 00 00") == ["4B 41 60 00 40 02 00 00"]


def test_nanotec_article_write_target_position() -> None:
    server, store = make(LengthCheck.SPECIFIC)
    assert ask(server, "23 7A 60 00 E8 03 00 00") == ["60 7A 60 00 00 00 00 00"]
    assert store.get(0x607A) == 1000


# ----------------------------------------------------------------------- expedited transfers


@pytest.mark.parametrize(
    ("request_", "answer"),
    [
        ("40 00 10 00 00 00 00 00", "43 00 10 00 92 01 02 00"),  # 4 bytes
        ("40 07 20 00 00 00 00 00", "47 07 20 00 56 34 12 00"),  # 3 bytes (UNSIGNED24)
        ("40 41 60 00 00 00 00 00", "4B 41 60 00 40 02 00 00"),  # 2 bytes
        ("40 01 10 00 00 00 00 00", "4F 01 10 00 00 00 00 00"),  # 1 byte
        ("40 00 30 00 00 00 00 00", "80 00 30 00 00 00 02 06"),  # no object
        ("40 06 20 09 00 00 00 00", "80 06 20 09 11 00 09 06"),  # no sub-index
    ],
)
def test_expedited_upload(request_: str, answer: str) -> None:
    server, _ = make()
    assert ask(server, request_) == [answer]


@pytest.mark.parametrize(
    ("request_", "index", "value"),
    [
        ("2F 60 60 00 FE 00 00 00", 0x6060, -2),
        ("2B 40 60 00 0F 00 00 00", 0x6040, 0x0F),
        ("27 07 20 00 01 02 03 00", 0x2007, 0x030201),
        ("23 FF 60 00 18 FC FF FF", 0x60FF, -1000),
        # 22h: size not indicated, the object's size decides (CiA 301)
        ("22 40 60 00 06 00 AA BB", 0x6040, 0x06),
        ("22 60 60 00 03 AA BB CC", 0x6060, 3),
        ("22 FF 60 00 E8 03 00 00", 0x60FF, 1000),
    ],
)
def test_expedited_download(request_: str, index: int, value: int) -> None:
    server, store = make()
    answer = request_[3:11]  # index and sub-index echoed
    assert ask(server, request_) == [f"60 {answer} 00 00 00 00"]
    assert store.get(index) == value


@pytest.mark.parametrize("length_check", list(LengthCheck))
def test_expedited_download_errors_from_the_object_dictionary(length_check: LengthCheck) -> None:
    server, _ = make(length_check)
    assert ask(server, "2B 41 60 00 00 00 00 00") == ["80 41 60 00 02 00 01 06"]  # read-only
    assert ask(server, "23 00 30 00 00 00 00 00") == ["80 00 30 00 00 00 02 06"]  # no object
    assert ask(server, "22 41 60 00 00 00 00 00") == ["80 41 60 00 02 00 01 06"]


def test_short_frames_are_ignored() -> None:
    server, store = make()
    assert ask(server, "23 FF 60 00 E8 03 00") == []
    assert ask(server, "40 41 60 00") == []
    assert store.get(0x60FF) == 0


# ---------------------------------------------------------------------- segmented transfers


def test_segmented_download() -> None:
    server, store = make()
    assert ask(server, "21 08 20 00 0B 00 00 00") == ["60 08 20 00 00 00 00 00"]
    assert ask(server, "00 48 45 4C 4C 4F 20 57") == ["20 00 00 00 00 00 00 00"]
    assert store.get_value(0x2008) == ""  # stored only when the last segment arrives
    # toggle 1, n = 3, c = 1
    assert ask(server, "17 4F 52 4C 44 00 00 00") == ["30 00 00 00 00 00 00 00"]
    assert store.get_value(0x2008) == "HELLO WORLD"


def test_segmented_download_without_size() -> None:
    server, store = make()
    assert ask(server, "20 00 22 00 00 00 00 00") == ["60 00 22 00 00 00 00 00"]
    assert ask(server, "00 01 02 03 04 05 06 07") == ["20 00 00 00 00 00 00 00"]
    assert ask(server, "1D 08 00 00 00 00 00 00") == ["30 00 00 00 00 00 00 00"]  # n = 6
    assert store.get_value(0x2200) == h("01 02 03 04 05 06 07 08")


def test_segmented_download_toggle_error() -> None:
    server, store = make()
    ask(server, "21 08 20 00 0B 00 00 00")
    ask(server, "00 48 45 4C 4C 4F 20 57")
    # the second segment repeats toggle 0
    assert ask(server, "07 4F 52 4C 44 00 00 00") == ["80 08 20 00 00 00 03 05"]
    assert store.get_value(0x2008) == ""
    assert ask(server, "17 4F 52 4C 44 00 00 00") == ["80 00 00 00 01 00 04 05"]  # dropped


def test_segmented_download_size_mismatch() -> None:
    server, store = make()
    ask(server, "21 08 20 00 0B 00 00 00")
    assert ask(server, "0B 48 45 4C 4C 00 00 00") == ["80 08 20 00 10 00 07 06"]
    assert store.get_value(0x2008) == ""


def test_segmented_download_refused_by_the_object_dictionary() -> None:
    server, _ = make()
    assert ask(server, "21 08 10 00 05 00 00 00") == ["60 08 10 00 00 00 00 00"]
    assert ask(server, "05 41 42 43 44 45 00 00") == ["80 08 10 00 02 00 01 06"]  # const


def test_segmented_upload_toggle_error() -> None:
    server, _ = make()
    ask(server, "40 08 10 00 00 00 00 00")
    assert ask(server, "70 00 00 00 00 00 00 00") == ["80 08 10 00 00 00 03 05"]
    assert ask(server, "60 00 00 00 00 00 00 00") == ["80 00 00 00 01 00 04 05"]


def test_empty_value_uploads_segmented_with_size_zero() -> None:
    server, _ = make()
    assert ask(server, "40 00 22 00 00 00 00 00") == ["41 00 22 00 00 00 00 00"]
    assert ask(server, "60 00 00 00 00 00 00 00") == ["0F 00 00 00 00 00 00 00"]


def test_client_abort_cancels_silently() -> None:
    server, _ = make()
    ask(server, "40 08 10 00 00 00 00 00")
    assert ask(server, "80 08 10 00 00 00 04 05") == []
    assert ask(server, "60 00 00 00 00 00 00 00") == ["80 00 00 00 01 00 04 05"]


def test_new_initiate_replaces_a_transfer_in_progress() -> None:
    server, _ = make()
    ask(server, "40 08 10 00 00 00 00 00")
    assert ask(server, "40 41 60 00 00 00 00 00") == ["4B 41 60 00 40 02 00 00"]
    assert ask(server, "60 00 00 00 00 00 00 00") == ["80 00 00 00 01 00 04 05"]


def test_segment_request_in_the_wrong_transfer_aborts_it() -> None:
    server, _ = make()
    ask(server, "40 08 10 00 00 00 00 00")
    assert ask(server, "00 41 42 43 44 45 46 47") == ["80 08 10 00 01 00 04 05"]


# -------------------------------------------------------------------------------- timeouts


def test_stalled_transfer_times_out() -> None:
    server, _ = make()
    ask(server, "40 08 10 00 00 00 00 00", now=10.0)
    assert server.poll(10.5) == []
    assert server.poll(11.0) == []  # exactly the timeout: still waiting
    assert [r.hex(" ").upper() for r in server.poll(11.01)] == ["80 08 10 00 00 00 04 05"]
    assert server.poll(20.0) == []  # reported once, transfer dropped
    assert ask(server, "60 00 00 00 00 00 00 00", now=20.0) == ["80 00 00 00 01 00 04 05"]


def test_each_client_frame_restarts_the_timeout() -> None:
    server, _ = make()
    ask(server, "40 08 10 00 00 00 00 00", now=0.0)
    ask(server, "60 00 00 00 00 00 00 00", now=0.9)
    assert server.poll(1.5) == []
    assert ask(server, "70 00 00 00 00 00 00 00", now=1.8) == ["17 4F 50 45 4E 00 00 00"]


def test_timeout_is_configurable_and_expedited_never_times_out() -> None:
    store = ObjectStore(make_od(), NODE, length_check=LengthCheck.GENERIC)
    server = SdoServer(store, block_transfer=False, timeout=0.1)
    assert [r.hex(" ").upper() for r in server.on_request(h("40 41 60 00 00 00 00 00"), 0.0)]
    assert server.poll(5.0) == []
    server.on_request(h("21 08 20 00 0B 00 00 00"), 5.0)
    assert [r.hex(" ").upper() for r in server.poll(5.2)] == ["80 08 20 00 00 00 04 05"]


def test_reset_drops_the_transfer() -> None:
    server, _ = make()
    ask(server, "40 08 10 00 00 00 00 00")
    server.reset()
    assert server.poll(100.0) == []
    assert ask(server, "60 00 00 00 00 00 00 00") == ["80 00 00 00 01 00 04 05"]


# ------------------------------------------------------------------------- block transfers

BLOB = bytes(range(0x30, 0x30 + 20))  # 20 bytes: segments of 7, 7 and 6


def _crc(data: bytes) -> str:
    return crc16(data).to_bytes(2, "little").hex(" ").upper()


def test_crc16_is_ccitt_with_zero_init() -> None:
    assert crc16(b"123456789") == 0x31C3  # CRC-16/XMODEM check value


def test_block_download_with_crc() -> None:
    server, store = make(block=True)
    # cc = 1, s = 1, size 20 -> sc = 1, blksize 127
    assert ask(server, "C6 00 22 00 14 00 00 00") == ["A4 00 22 00 7F 00 00 00"]
    assert ask(server, "01 " + BLOB[0:7].hex(" ")) == []
    assert ask(server, "02 " + BLOB[7:14].hex(" ")) == []
    assert ask(server, "83 " + BLOB[14:20].hex(" ") + " 00") == ["A2 03 7F 00 00 00 00 00"]
    assert store.get_value(0x2200) == b""  # written at the end, after the CRC check
    # end: n = 1 unused byte in the last segment -> C1h | 1 << 2
    assert ask(server, f"C5 {_crc(BLOB)} 00 00 00 00 00") == ["A1 00 00 00 00 00 00 00"]
    assert store.get_value(0x2200) == BLOB


def test_block_download_crc_error() -> None:
    server, store = make(block=True)
    ask(server, "C6 00 22 00 07 00 00 00")
    assert ask(server, "81 " + BLOB[0:7].hex(" ")) == ["A2 01 7F 00 00 00 00 00"]
    assert ask(server, "C1 00 00 00 00 00 00 00") == ["80 00 22 00 04 00 04 05"]
    assert store.get_value(0x2200) == b""


def test_block_download_without_crc_ignores_the_crc_field() -> None:
    server, store = make(block=True)
    ask(server, "C2 00 22 00 07 00 00 00")  # cc = 0
    ask(server, "81 " + BLOB[0:7].hex(" "))
    assert ask(server, "C1 00 00 00 00 00 00 00") == ["A1 00 00 00 00 00 00 00"]
    assert store.get_value(0x2200) == BLOB[0:7]


def test_block_download_bad_sequence_number() -> None:
    server, store = make(block=True)
    ask(server, "C6 00 22 00 14 00 00 00")
    ask(server, "01 " + BLOB[0:7].hex(" "))
    assert ask(server, "03 " + BLOB[7:14].hex(" ")) == ["80 00 22 00 03 00 04 05"]
    assert ask(server, "C5 00 00 00 00 00 00 00") == ["80 00 00 00 01 00 04 05"]  # dropped
    assert store.get_value(0x2200) == b""


def test_block_download_refused_by_the_object_dictionary_at_the_end() -> None:
    server, _ = make(LengthCheck.SPECIFIC, block=True)
    ask(server, "C6 FF 60 00 07 00 00 00")  # 7 bytes into an INTEGER32
    ask(server, "81 " + BLOB[0:7].hex(" "))
    assert ask(server, f"C1 {_crc(BLOB[0:7])} 00 00 00 00 00") == ["80 FF 60 00 12 00 07 06"]


def test_block_download_client_abort_inside_a_block() -> None:
    server, _ = make(block=True)
    ask(server, "C6 00 22 00 14 00 00 00")
    ask(server, "01 " + BLOB[0:7].hex(" "))
    assert ask(server, "80 00 22 00 00 00 04 05") == []
    assert server.poll(100.0) == []


def test_block_upload_with_crc() -> None:
    server, store = make(block=True)
    store.set_value(0x2200, 0, BLOB)
    # cc = 1, blksize 127, pst 0 -> sc = 1, s = 1, size 20
    assert ask(server, "A4 00 22 00 7F 00 00 00") == ["C6 00 22 00 14 00 00 00"]
    assert ask(server, "A3 00 00 00 00 00 00 00") == [
        "01 " + BLOB[0:7].hex(" ").upper(),
        "02 " + BLOB[7:14].hex(" ").upper(),
        "83 " + BLOB[14:20].hex(" ").upper() + " 00",
    ]
    # all three acknowledged -> end: n = 1, CRC of the 20 bytes
    assert ask(server, "A2 03 7F 00 00 00 00 00") == [f"C5 {_crc(BLOB)} 00 00 00 00 00"]
    assert ask(server, "A1 00 00 00 00 00 00 00") == []
    assert ask(server, "A1 00 00 00 00 00 00 00") == ["80 00 00 00 01 00 04 05"]  # done


def test_block_upload_in_blocks_of_two_with_retransmission() -> None:
    server, store = make(block=True)
    store.set_value(0x2200, 0, BLOB)
    ask(server, "A4 00 22 00 02 00 00 00")
    first = ["01 " + BLOB[0:7].hex(" ").upper(), "02 " + BLOB[7:14].hex(" ").upper()]
    assert ask(server, "A3 00 00 00 00 00 00 00") == first
    # only segment 1 arrived: the next block starts with the second 7 bytes
    assert ask(server, "A2 01 02 00 00 00 00 00") == [
        "01 " + BLOB[7:14].hex(" ").upper(),
        "82 " + BLOB[14:20].hex(" ").upper() + " 00",
    ]
    assert ask(server, "A2 02 02 00 00 00 00 00") == [f"C5 {_crc(BLOB)} 00 00 00 00 00"]


def test_block_upload_of_empty_value() -> None:
    server, _ = make(block=True)
    assert ask(server, "A4 00 22 00 7F 00 00 00") == ["C6 00 22 00 00 00 00 00"]
    # one segment, c = 1, no data; the end says all 7 bytes unused (n = 7 -> DDh)
    assert ask(server, "A3 00 00 00 00 00 00 00") == ["81 00 00 00 00 00 00 00"]
    assert ask(server, "A2 01 7F 00 00 00 00 00") == [f"DD {_crc(b'')} 00 00 00 00 00"]


@pytest.mark.parametrize(
    ("requests", "answer"),
    [
        (["A4 00 22 00 00 00 00 00"], "80 00 22 00 02 00 04 05"),  # blksize 0
        (["A4 00 22 00 80 00 00 00"], "80 00 22 00 02 00 04 05"),  # blksize 128
        (["A4 00 22 00 7F 00 00 00", "A3 00 00 00 00 00 00 00", "A2 09 7F 00 00 00 00 00"],
         "80 00 22 00 03 00 04 05"),  # acknowledges more segments than were sent
        (["A4 00 22 00 7F 00 00 00", "A2 00 7F 00 00 00 00 00"],
         "80 00 22 00 01 00 04 05"),  # ack before start
        (["A4 00 30 00 7F 00 00 00"], "80 00 30 00 00 00 02 06"),  # no object
    ],
)  # fmt: skip
def test_block_upload_errors(requests: list[str], answer: str) -> None:
    server, store = make(block=True)
    store.set_value(0x2200, 0, BLOB)
    replies: list[str] = []
    for request_ in requests:
        replies = ask(server, request_)
    assert replies == [answer]


def test_block_upload_times_out_waiting_for_the_acknowledge() -> None:
    server, _ = make(block=True)
    ask(server, "A4 00 10 00 7F 00 00 00", now=0.0)  # 1000h
    ask(server, "A3 00 00 00 00 00 00 00", now=0.5)
    assert [r.hex(" ").upper() for r in server.poll(1.6)] == ["80 00 10 00 00 00 04 05"]


# ------------------------------------------------------ interop with python-canopen's client


class _BusSdoServer:
    """Serves SdoServer on its own virtual-bus instance from a thread, like a real node."""

    def __init__(self, channel: str, server: SdoServer) -> None:
        self.bus = can.Bus(interface="virtual", channel=channel)
        self._server = server
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="sdo-server", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.is_set():
            message = self.bus.recv(timeout=0.05)
            if message is None or message.arbitration_id != 0x600 + NODE:
                continue
            # The server's clock is not under test here: no transfer stalls.
            for reply in self._server.on_request(bytes(message.data), 0.0):
                self.bus.send(
                    can.Message(arbitration_id=0x580 + NODE, data=reply, is_extended_id=False)
                )

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=5.0)
        self.bus.shutdown()


@pytest.fixture
def remote(request: pytest.FixtureRequest) -> Iterator[tuple[canopen.RemoteNode, ObjectStore]]:
    channel = f"sdo-interop-{request.node.name}"
    store = ObjectStore(make_od(), NODE, length_check=LengthCheck.SPECIFIC)
    serving = _BusSdoServer(channel, SdoServer(store, block_transfer=True))
    network = canopen.Network()
    network.NOTIFIER_CYCLE = 0.05  # the notifier thread notices disconnect() this fast
    network.connect(interface="virtual", channel=channel)
    try:
        node = network.add_node(NODE, make_od())
        yield node, store
    finally:
        network.disconnect()
        serving.close()


def test_canopen_client_expedited(remote: tuple[canopen.RemoteNode, ObjectStore]) -> None:
    node, store = remote
    assert node.sdo.upload(0x6041, 0) == h("40 02")
    node.sdo.download(0x60FF, 0, (-1000).to_bytes(4, "little", signed=True))
    assert store.get(0x60FF) == -1000


def test_canopen_client_segmented(remote: tuple[canopen.RemoteNode, ObjectStore]) -> None:
    node, store = remote
    assert node.sdo.upload(0x1008, 0) == b"DVS_CANOPEN"
    node.sdo.download(0x2200, 0, BLOB)
    assert store.get_value(0x2200) == BLOB


def test_canopen_client_block(remote: tuple[canopen.RemoteNode, ObjectStore]) -> None:
    node, store = remote
    payload = bytes(range(256)) * 4  # 1024 bytes: more than one block of 127 segments
    with node.sdo.open(0x2200, 0, "wb", size=len(payload), block_transfer=True) as writer:
        writer.write(payload)
    assert store.get_value(0x2200) == payload
    store.set_value(0x2200, 0, payload[::-1])
    with node.sdo.open(0x2200, 0, "rb", block_transfer=True) as reader:
        assert reader.read() == payload[::-1]


def test_canopen_client_sees_abort_codes(remote: tuple[canopen.RemoteNode, ObjectStore]) -> None:
    node, _ = remote
    with pytest.raises(canopen.SdoAbortedError) as raised:
        node.sdo.download(0x6041, 0, h("00 00"))
    assert raised.value.code == 0x06010002
