"""CSV logs come in several layouts: python-can's own (its reader), SavvyCAN's GVRET CSV (read
here, streamed), and others that are refused in one line naming the layouts that are read.

SavvyCAN: `Time Stamp,ID,Extended,Dir,Bus,LEN,D1,...,D8` (older files have no Dir; CAN FD
files run past D8): timestamps in microseconds, the ID in hex (with or without 0x), Extended
true/false, one data byte in hex per D column.
"""

from __future__ import annotations

import gzip
import os
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TextIO

PYTHON_CAN_HEADER = "timestamp,arbitration_id,extended,remote,error,dlc,data"
SAVVYCAN_HEADER = "Time Stamp,ID,Extended,Dir,Bus,LEN,D1,...,D8"
EXPECTED = f"python-can's CSV ({PYTHON_CAN_HEADER}) or SavvyCAN's ({SAVVYCAN_HEADER})"
_PROGRESS_EVERY = 4096
_REQUIRED = ("time stamp", "id", "extended", "len")
EXTENDED = 0x20000000  # as reader.EXTENDED: a 29-bit id can never pass for an 11-bit one
Frame = tuple[float, int, bytes]


class CsvLayoutError(ValueError):
    """A CSV whose header is no layout this tool reads."""


def _open(path: Path) -> TextIO:
    if path.suffix == ".gz":
        return gzip.open(path, "rt", encoding="utf-8", errors="replace", newline="")
    return path.open(encoding="utf-8", errors="replace", newline="")


def _columns(line: str) -> list[str]:
    return [cell.strip().lower() for cell in line.lstrip("\ufeff").split(",")]


def layout(path: Path) -> str:
    """ "python-can" or "savvycan" from the header line; CsvLayoutError for anything else."""
    with _open(path) as file:
        header = file.readline().strip()
    columns = _columns(header)
    if ",".join(columns) == PYTHON_CAN_HEADER:
        return "python-can"
    if all(name in columns for name in _REQUIRED) and "d1" in columns:
        return "savvycan"
    shown = header[:80] + ("…" if len(header) > 80 else "")
    raise CsvLayoutError(f"a CSV layout this tool does not read (header {shown!r});"
                         f" it reads {EXPECTED}")  # fmt: skip


def read_savvycan(path: Path, progress: Callable[[int], None] | None = None) -> Iterator[Frame]:
    """Every frame of a SavvyCAN CSV in file order."""
    with _open(path) as file:
        columns = _columns(file.readline())
        at = {name: columns.index(name) for name in _REQUIRED}
        first_data = columns.index("d1")
        done = 0  # characters read: close enough to bytes for a progress bar
        for number, line in enumerate(file, start=2):
            done += len(line)
            if not line.strip():
                continue
            cells = [cell.strip() for cell in line.split(",")]
            try:
                time = float(cells[at["time stamp"]]) / 1e6  # microseconds
                can_id = int(cells[at["id"]].removeprefix("0x").removeprefix("0X"), 16)
                extended = cells[at["extended"]].lower() in ("true", "1")
                length = int(cells[at["len"]])
                data = bytes(int(b, 16) for c in cells[first_data:] for b in c.split())[:length]
            except (ValueError, IndexError):
                raise ValueError(
                    f"line {number} is not a SavvyCAN CSV row: {line[:60]!r}"
                ) from None
            if len(data) != length or not 0 <= can_id <= 0x1FFFFFFF:
                raise ValueError(f"line {number} is not a SavvyCAN CSV row: {line[:60]!r}")
            yield time, can_id + EXTENDED if extended else can_id, data
            if progress is not None and number % _PROGRESS_EVERY == 0:
                progress(done)
    if progress is not None:
        progress(os.path.getsize(path))
