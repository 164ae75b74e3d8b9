"""BLF files that declare or expand to sizes no real log has are refused at the first such
size, with words saying so, and nothing is decoded or stored (logs/blf.py)."""

from __future__ import annotations

import gzip
from pathlib import Path

import can
import pytest
from can.io.blf import LOG_CONTAINER
from fastapi.testclient import TestClient

from servodesk.logs.blf import MAX_CONTAINER, LogBoundsError
from servodesk.logs.reader import EXTENDED, read_frames
from tests.blf_bombs import (
    FOUR_GB,
    REAL_CONTAINER,
    container,
    deflate,
    file_header,
    header,
    inner_claim,
    obj,
    zlib_bomb,
)

# Small enough to build in milliseconds, still 64 times what each container declares.
BOMB = zlib_bomb(expands_to=8 * 1024 * 1024, containers=3)


def _refusal(tmp_path: Path, data: bytes, name: str = "bomb.blf") -> str:
    path = tmp_path / name
    path.write_bytes(data)
    with pytest.raises(LogBoundsError) as caught:
        list(read_frames(path))
    return str(caught.value)


def test_a_container_expanding_past_its_declaration_is_refused_at_the_first(
    tmp_path: Path,
) -> None:
    message = _refusal(tmp_path, BOMB)
    assert message.startswith("damaged or hostile BLF file: container 1 (byte 144)")
    assert f"expands past the {REAL_CONTAINER} bytes it declares" in message
    assert message.endswith("nothing was decoded")


def test_an_object_claiming_4_gb_is_refused(tmp_path: Path) -> None:
    # an honest container (it expands to what it declares) whose first object claims 4 GB
    inside = inner_claim() + bytes(1000)
    honest = container(deflate(inside, 0), len(inside))
    message = _refusal(tmp_path, file_header(1) + honest)
    assert f"an object in container 1 (byte 144) claims {FOUR_GB} bytes" in message


def test_a_top_level_object_claiming_4_gb_is_refused(tmp_path: Path) -> None:
    claimed = container(deflate(b"", 1000), 1000, claim=FOUR_GB)
    message = _refusal(tmp_path, file_header(1) + claimed)
    assert f"container 1 (byte 144) claims {FOUR_GB} bytes" in message


def test_a_container_declaring_more_than_any_real_one_is_refused(tmp_path: Path) -> None:
    big = container(deflate(b"", 1000), MAX_CONTAINER + 1)
    message = _refusal(tmp_path, file_header(1) + big)
    assert f"declares {MAX_CONTAINER + 1} bytes uncompressed" in message


@pytest.mark.parametrize("claim", [FOUR_GB, 0])
def test_a_file_header_claiming_a_size_no_header_has_is_refused(tmp_path: Path, claim: int) -> None:
    # python-can reads that much to skip it (all of the file for a size below its own)
    message = _refusal(tmp_path, header(claim) + obj(LOG_CONTAINER, bytes(16)))
    assert f"its header claims {claim} bytes" in message


def test_a_gzipped_bomb_is_refused_too(tmp_path: Path) -> None:
    message = _refusal(tmp_path, gzip.compress(BOMB), "bomb.blf.gz")
    assert "container 1 (byte 144)" in message


def test_real_blf_files_read_as_before(tmp_path: Path) -> None:
    """Frames spanning many containers (python-can writes 128 kB each) and objects split
    across two containers read the same through the bounded reader as through python-can."""
    path = tmp_path / "real.blf"
    with can.BLFWriter(path) as writer:
        for i in range(20_000):
            writer.on_message_received(
                can.Message(
                    timestamp=1_700_000_000 + i / 1000,
                    arbitration_id=(0x180 + i % 4) if i % 3 else 0x1ABCDE0,
                    is_extended_id=not i % 3,
                    data=i.to_bytes(4, "little") + bytes(i % 5),
                )
            )
    ours = list(read_frames(path))
    with can.BLFReader(path) as reader:
        theirs = [
            (m.timestamp, m.arbitration_id + (EXTENDED if m.is_extended_id else 0), bytes(m.data))
            for m in reader
        ]
    assert len(ours) == 20_000
    assert ours == theirs


def test_the_api_refuses_the_bomb_and_stores_nothing(client: TestClient, tmp_path: Path) -> None:
    files = {"file": ("bomb.blf", BOMB, "application/octet-stream")}
    answer = client.post("/api/logs/decode", files=files)
    assert answer.status_code == 422, answer.text
    body = answer.json()
    assert body["error"] == "invalid_value"
    assert body["message"] == (
        "bomb.blf: damaged or hostile BLF file: container 1 (byte 144) expands past the "
        f"{REAL_CONTAINER} bytes it declares; nothing was decoded"
    )
    assert not list((tmp_path / "logs").glob("*"))  # no result, not even a partial one
    assert not list((tmp_path / "uploads").glob("*"))  # the spooled upload is gone
