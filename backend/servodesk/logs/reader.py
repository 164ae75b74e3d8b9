"""Frames from a CAN log file in any format python-can reads (candump .log, .asc, .blf, .trc,
.csv, .mf4 through asammdf), streamed: one frame in memory at a time (an .mf4 is read by
asammdf, which loads the file's CAN data group).

Frames are (time s, CAN id, data). An extended (29-bit) id is returned with EXTENDED added, so
it can never be mistaken for an 11-bit CANopen id; error frames are skipped and counted.
"""

from __future__ import annotations

import gzip
import math
import os
import re
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any, BinaryIO, cast

import can

from servodesk.logs import csv_layouts
from servodesk.logs.blf import BoundedBlfReader, LogBoundsError

EXTENDED = 0x20000000  # added to a 29-bit id (the COB-ID "frame" bit, CiA 301)
_CAN_ERR_FLAG = 0x20000000  # Linux can.h: the id of an error frame has this bit
PROGRESS_EVERY = 4096  # frames between progress reports
SUFFIXES = (".log", ".asc", ".blf", ".trc", ".csv", ".mf4")
Frame = tuple[float, int, bytes]
_HEX_ID = re.compile(rb"[0-9A-Fa-f]{1,8}")
CANDUMP_LAYOUT = "candump -l: '(1700000000.000000) can0 181#0102'"
# the layout python-can's reader for a suffix expects, said when it cannot read a file
EXPECTED = {
    ".csv": csv_layouts.EXPECTED,
    ".trc": "PEAK's TRC (PCAN-View, file versions 1.0 to 2.1)",
    ".asc": "Vector's ASC",
    ".blf": "Vector's BLF",
    ".mf4": "ASAM MDF 4 with a CAN bus logging group",
}


class LogFormatError(ValueError):
    """The file is not a log python-can can read."""


def read_frames(
    path: Path, *, progress: Callable[[int], None] | None = None, skipped: list[int] | None = None
) -> Iterator[Frame]:
    """Every data/remote frame of `path` in file order. `progress(bytes_read)` is called every
    few thousand frames; `skipped[0]` counts the error frames left out."""
    suffix = "".join(path.suffixes[-2:]) if path.suffix == ".gz" else path.suffix
    if suffix.removesuffix(".gz").lower() not in SUFFIXES:
        raise LogFormatError(
            f"{path.name}: unknown log format {suffix or '(no suffix)'!r};"
            f" use one of {', '.join(SUFFIXES)}"
        )
    if suffix.lower() == ".log":
        yield from _candump(path, progress, skipped)
        return
    # csv_layouts.layout raises CsvLayoutError, a ValueError naming the layouts it reads
    if suffix.lower().removesuffix(".gz") == ".csv" and csv_layouts.layout(path) == "savvycan":
        yield from csv_layouts.read_savvycan(path, progress)
        return
    try:
        reader: Any = _open_reader(path, suffix.lower())
    except LogBoundsError:
        raise  # its own words: which size, and that nothing was decoded
    except ImportError as error:  # MF4 without asammdf (a dependency: a broken install)
        raise LogFormatError(f"{path.name}: {error}") from error
    except Exception as error:  # the reader's complaint: BLFParseError, struct.error, ...
        raise ValueError(
            f"not a readable {suffix} log (its header): {error}{_expected(suffix)}"
        ) from error
    tell = _position_of(reader)
    count = 0
    try:
        for msg in _checked(reader, suffix):
            if msg.is_error_frame:
                if skipped is not None:
                    skipped[0] += 1
                continue
            can_id = msg.arbitration_id + EXTENDED if msg.is_extended_id else msg.arbitration_id
            yield msg.timestamp, can_id, msg.data
            count += 1
            if progress is not None and count % PROGRESS_EVERY == 0:
                progress(tell())
    finally:
        reader.stop()
    if progress is not None:
        progress(os.path.getsize(path))


def _open_reader(path: Path, suffix: str) -> Any:
    """python-can's reader for the suffix; for BLF its subclass that bounds every size."""
    if suffix == ".blf":
        return BoundedBlfReader(path)
    if suffix == ".blf.gz":
        return BoundedBlfReader(cast(BinaryIO, gzip.open(path, "rb")))
    return can.LogReader(path)


def _checked(reader: Any, suffix: str) -> Iterator[Any]:
    """The reader's messages; its complaint about a damaged file (zlib.error, struct.error,
    BLFParseError...) as a ValueError naming the frame it stopped after, like its own
    ValueErrors (the CLI and the service report those as "cannot read the log")."""
    count = 0
    iterator = iter(reader)
    while True:
        try:
            msg = next(iterator)
        except StopIteration:
            return
        except LogBoundsError:
            raise
        except Exception as error:
            raise ValueError(
                f"not a readable {suffix} log after frame {count}: {error}{_expected(suffix)}"
            ) from error
        count += 1
        yield msg


def _expected(suffix: str) -> str:
    layout = EXPECTED.get(suffix.lower().removesuffix(".gz"))
    return f" (expected {layout})" if layout else ""


def _candump(
    path: Path, progress: Callable[[int], None] | None, skipped: list[int] | None
) -> Iterator[Frame]:
    """candump -l lines, `(1700000000.000000) can0 181#0102…`, parsed without building a
    can.Message per frame: python-can's reader took 80 % of the decode time (bench/log_decode.py).
    The same cases as python-can's CanutilsLogReader: RTR `R`, CAN FD `##`, extended ids
    (8 hex digits), error frames (CAN_ERR_FLAG in the id) skipped."""
    with path.open("rb") as file:
        for count, line in enumerate(file, start=1):
            close = line.find(b")")
            parts = line[close + 1 :].split()
            if close < 0 or len(parts) < 2 or b"#" not in parts[1]:
                if line.strip():
                    raise ValueError(
                        f"line {count} is not a candump frame: {line[:60]!r}"
                        f" (a .log is read as {CANDUMP_LAYOUT})"
                    )
                continue
            frame = parts[1]
            hash_at = frame.index(b"#")
            ident = frame[:hash_at]
            try:
                # int(x, 16) alone also takes "-1", "+7FF" and "1_0"
                can_id = int(ident, 16) if _HEX_ID.fullmatch(ident) else -1
                payload = frame[hash_at + 1 :]
                if payload[:1] == b"#":  # CAN FD: a flags nibble, then the data
                    payload = payload[2:]
                data = b"" if payload[:1] in (b"R", b"r") else bytes.fromhex(payload.decode())
                time = float(line[1:close])
            except ValueError:  # UnicodeDecodeError too
                can_id, data, time = -1, b"", math.nan
            if can_id < 0 or len(data) > 64 or not math.isfinite(time):
                raise ValueError(
                    f"line {count} is not a candump frame: {line[:60]!r}"
                    f" (a .log is read as {CANDUMP_LAYOUT})"
                )
            if len(ident) > 3:  # 29-bit id, or an error frame
                if can_id & _CAN_ERR_FLAG:
                    if skipped is not None:
                        skipped[0] += 1
                    continue
                can_id = (can_id & 0x1FFFFFFF) + EXTENDED
            yield time, can_id, data
            if progress is not None and count % PROGRESS_EVERY == 0:
                progress(file.tell())
    if progress is not None:
        progress(os.path.getsize(path))


def _position_of(reader: Any) -> Callable[[], int]:
    """How far into the file the reader is, in bytes (text readers: their buffer's position,
    which runs ahead by one read chunk; good enough for a progress bar)."""
    file = getattr(reader, "file", None)
    raw = getattr(file, "buffer", file)
    if raw is not None and hasattr(raw, "tell"):

        def tell() -> int:
            try:
                return int(raw.tell())
            except (OSError, ValueError):
                return 0

        return tell
    return lambda: 0
