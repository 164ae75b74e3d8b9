"""The SDO frames written once in servodesk_protocol.sdo, as bytes (CiA 301 §7.2.4.3), and
what the app's listeners built on them recognise."""

from __future__ import annotations

import pytest

from servodesk.pdo.write_watch import written_object
from servodesk_protocol import sdo


def test_built_frames() -> None:
    assert sdo.upload_request(0x1000, 0).hex(" ") == "40 00 10 00 00 00 00 00"
    assert sdo.expedited_download(0x60C1, 1, 4).hex(" ") == "23 c1 60 01"
    assert sdo.expedited_download(0x6060, 0, 1).hex(" ") == "2f 60 60 00"
    assert sdo.expedited_download(0x6040, 0, 2).hex(" ") == "2b 40 60 00"
    assert sdo.abort_frame(0x1018, 1, 0x06020000).hex(" ") == "80 18 10 01 00 00 02 06"
    with pytest.raises(ValueError, match="1 to 4"):
        sdo.expedited_download(0x6040, 0, 5)


@pytest.mark.parametrize(
    ("frame", "parsed"),
    [
        ("80 18 10 01 00 00 02 06", (0x1018, 1, 0x06020000)),
        ("80 18 10 01 00 00 02", None),  # short
        ("43 18 10 01 00 00 02 06", None),  # an upload answer
    ],
)
def test_parse_abort(frame: str, parsed: tuple[int, int, int] | None) -> None:
    assert sdo.parse_abort(bytes.fromhex(frame)) == parsed


@pytest.mark.parametrize(
    ("can_id", "frame", "found"),
    [
        (0x603, "23 00 18 01 83 01 00 80", (3, 0x1800, 1)),  # expedited download
        (0x603, "21 00 1a 00 08 00 00 00", (3, 0x1A00, 0)),  # segmented download initiate
        (0x603, "c2 00 16 01 08 00 00 00", (3, 0x1600, 1)),  # block download initiate
        (0x603, "c1 00 00 00 00 00 00 00", None),  # block download end
        (0x603, "40 00 18 01 00 00 00 00", None),  # an upload (a read)
        (0x583, "60 00 18 01 00 00 00 00", None),  # the server's answer
        (0x603, "23 00", None),  # short
    ],
)
def test_written_object(can_id: int, frame: str, found: tuple[int, int, int] | None) -> None:
    assert written_object(can_id, bytes.fromhex(frame)) == found
