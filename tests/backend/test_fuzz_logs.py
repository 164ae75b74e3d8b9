"""Property-based fuzzing of the offline CAN log decoder behind `POST /api/logs/decode`.

Valid logs are written with python-can's own writers from the recorded commissioning session
(tests/backend/log_session.py), then mutated: bytes flipped, inserted, deleted, lines dropped,
duplicated or garbled, the file truncated. The entry point is the decode worker's own call (what
the route runs in a worker process): it must return a decoded result or raise LogReadError (a 422),
and the reader underneath must fail only with a ValueError that says where (a line, a frame
count), never e.g. a zlib.error, a BLFParseError or a negative CAN id getting into the decoder.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from servodesk.logs.decode_worker import LogReadError
from servodesk.logs.decode_worker import _decode as decode_in_worker
from servodesk.logs.reader import LogFormatError, read_frames
from servodesk.logs.store import LogResult
from tests.backend.log_session import record, write_log

TEXT_FORMATS = (".log", ".asc", ".trc", ".csv")
BINARY_FORMATS = (".blf",)
_LOGS: dict[str, bytes] = {}
_FRAMES: list[int] = []  # how many frames the session has


def _log(suffix: str) -> bytes:
    if not _LOGS:
        frames = record()  # ~160 frames: boot-ups, SDO transfers, heartbeats, EMCYs
        _FRAMES.append(len(frames))
        with tempfile.TemporaryDirectory() as tmp:
            for fmt in TEXT_FORMATS + BINARY_FORMATS:
                path = Path(tmp) / f"session{fmt}"
                write_log(frames, path)
                _LOGS[fmt] = path.read_bytes()
    return _LOGS[suffix]


GARBAGE = (
    b"",
    b"(",
    b")",
    b"#",
    b"##",
    b"(1700000000.0) can0 -1#00",
    b"(1700000000.0) can0 1_0#00",
    b"(1700000000.0) can0 +7FF#00",
    b"(1700000000.0) can0 \xff\xfe#00",
    b"(1700000000.0) can0 181#0",
    b"(1700000000.0) can0 181#ZZ",
    b"(1700000000.0) can0 181#\xff",
    b"(1700000000.0) can0 181##",
    b"(1700000000.0) can0 181##1" + b"00" * 100,
    b"(nan) can0 181#00",
    b"(inf) can0 181#00",
    b"(-1) can0 181#00",
    b"(1e999) can0 181#00",
    b"() can0 181#00",
    b"(1700000000.0) can0 FFFFFFFFFFFF#00",
    b"(1700000000.0) can0 20000000#00",
    b"(1700000000.0) can0 " + b"1" * 5000 + b"#00",
    b"(" + b"9" * 5000 + b") can0 181#00",
    b"   1.000000 1  181             Rx   d 8 01 02 03 04 05 06 07 08",
    b"   1.000000 1  181             Rx   d 9 01",
    b"   1.000000 1  ZZZ             Rx   d 1 01",
    b"   -1.000000 1  181             Rx   d 1 01",
    b"date Thu Nov 30 24:99:99.000 pm 2023",
    b"base hex  timestamps absolute",
    b"base oct  timestamps relative",
    b";$FILEVERSION=9.9",
    b";$STARTTIME=abc",
    b"     1)         1.0  Rx         0181  8  01 02",
    b"     1)         1.0  Rx         0181 -1  01 02",
    b"timestamp,arbitration_id,extended,remote,error,dlc,data",
    b"1.0,0x181,0,0,0,8,AQID",
    b"1.0,ZZ,0,0,0,8,AQID",
    b"1.0,0x181,0,0,0,8,!!!",
    b"\xff\xfe\x00\x80",
    b"A" * 100_000,
)


@st.composite
def _text_mutation(draw: st.DrawFn, data: bytes) -> bytes:
    kind = draw(st.sampled_from(("flip", "insert", "delete", "truncate", "line", "garbage")))
    size = len(data)
    if kind == "flip":
        at = draw(st.integers(0, size - 1))
        return data[:at] + bytes([data[at] ^ draw(st.integers(1, 255))]) + data[at + 1 :]
    if kind == "insert":
        at = draw(st.integers(0, size))
        return data[:at] + draw(st.binary(min_size=1, max_size=16)) + data[at:]
    if kind == "delete":
        at = draw(st.integers(0, size - 1))
        return data[:at] + data[at + draw(st.integers(1, 512)) :]
    if kind == "truncate":
        return data[: draw(st.integers(0, size))]
    lines = data.splitlines(keepends=True)
    if not lines:
        return data
    at = draw(st.integers(0, len(lines) - 1))
    if kind == "garbage":
        lines[at] = draw(st.sampled_from(GARBAGE)) + b"\n"
    else:
        lines[at : at + 1] = [lines[at]] * draw(st.sampled_from((0, 2, 3)))
    return b"".join(lines)


@st.composite
def _binary_mutation(draw: st.DrawFn, data: bytes) -> bytes:
    kind = draw(st.sampled_from(("flip", "insert", "delete", "truncate", "overwrite")))
    size = len(data)
    at = draw(st.integers(0, size - 1))
    if kind == "flip":
        return data[:at] + bytes([data[at] ^ draw(st.integers(1, 255))]) + data[at + 1 :]
    if kind == "insert":
        return data[:at] + draw(st.binary(min_size=1, max_size=16)) + data[at:]
    if kind == "delete":
        return data[:at] + data[at + draw(st.integers(1, 64)) :]
    if kind == "truncate":
        return data[:at]
    chunk = draw(st.sampled_from((b"\xff" * 4, b"\x00" * 4, b"\x7f\xff\xff\xff", b"LOBJ")))
    return data[:at] + chunk + data[at + len(chunk) :]


@st.composite
def logs(draw: st.DrawFn, formats: tuple[str, ...]) -> tuple[str, bytes]:
    suffix = draw(st.sampled_from(formats))
    data = _log(suffix)
    mutation = _binary_mutation if suffix in BINARY_FORMATS else _text_mutation
    for _ in range(draw(st.integers(1, 3))):
        if not data:
            break
        data = draw(mutation(data))
    return f"session{suffix}", data


def _decode(tmp: Path, name: str, data: bytes) -> LogResult | None:
    """The decode worker's own call, run here (the server runs it in a worker process); None
    for the route's 422. The store's own failure must be a ValueError (a named complaint
    about the file), which the worker then reports as words."""
    path = tmp / name
    path.write_bytes(data)
    complaint = ""
    try:
        for _time, can_id, frame in read_frames(path):
            assert 0 <= can_id < 0x40000000
            assert len(frame) <= 64
    except LogFormatError:
        raise  # the suffix is known: only the content can be wrong
    except ValueError as error:  # where it stopped: a line, a frame count, the header, or
        complaint = str(error)  # the byte where a BLF object's size is refused (logs/blf.py)
    assert not complaint or any(w in complaint for w in ("line", "frame", "header", "byte"))
    try:
        result = decode_in_worker(tmp, path, None)
    except LogReadError as error:
        complaint = str(error)
    else:
        complaint = ""
    if complaint:
        return None  # the route's 422, in the reader's words
    assert result.name == name
    assert result.stats["frames"] >= 0
    return result


FUZZ = settings(
    max_examples=150,
    derandomize=True,
    deadline=None,
    database=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)


@FUZZ
@given(logs(TEXT_FORMATS))
# regressions: candump ids int(x, 16) took ("-1", "1_0", "+7FF") and values without a line number
@example(("session.log", b"(1700000000.0) can0 -1#00\n"))
@example(("session.log", b"(1700000000.0) can0 1_0#00\n"))
@example(("session.log", b"(1700000000.0) can0 181#ZZ\n"))
@example(("session.log", b"(1700000000.0) can0 181#\xff\n"))
@example(("session.log", b"(abc) can0 181#00\n"))
def test_mutated_text_logs_decode_or_are_refused(tmp_path: Path, log: tuple[str, bytes]) -> None:
    with tempfile.TemporaryDirectory(dir=tmp_path) as tmp:
        _decode(Path(tmp), *log)


@settings(FUZZ, max_examples=60)
@given(logs(BINARY_FORMATS))
# regressions: python-can's BLFParseError / struct.error / zlib.error came out as they were
@example(("session.blf", b"NOT A BLF" * 40))
@example(("session.blf", b"LOGG" + bytes(300)))
def test_mutated_blf_logs_decode_or_are_refused(tmp_path: Path, log: tuple[str, bytes]) -> None:
    with tempfile.TemporaryDirectory(dir=tmp_path) as tmp:
        _decode(Path(tmp), *log)


@pytest.mark.parametrize("suffix", TEXT_FORMATS + BINARY_FORMATS)
def test_unmutated_logs_decode(tmp_path: Path, suffix: str) -> None:
    result = _decode(tmp_path, f"session{suffix}", _log(suffix))
    assert result is not None
    assert result.stats["frames"] == _FRAMES[0]
