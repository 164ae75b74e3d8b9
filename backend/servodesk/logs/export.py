"""Events out as text, CSV, JSON lines or Parquet, streamed (Parquet in row batches)."""

from __future__ import annotations

import csv
import json
from collections.abc import Iterable
from enum import StrEnum
from pathlib import Path
from typing import Any, Protocol, TextIO

from servodesk.logs.events import COLUMNS, Event, clock

PARQUET_BATCH = 65_536  # rows per Parquet row group


class ExportFormat(StrEnum):
    TEXT = "text"
    CSV = "csv"
    JSON = "json"  # JSON lines: one event object per line
    PARQUET = "parquet"


class EventWriter(Protocol):
    def write(self, event: Event) -> None: ...
    def close(self) -> None: ...


class TextWriter:
    def __init__(self, out: TextIO) -> None:
        self._out = out

    def write(self, event: Event) -> None:
        node = f"{event.node:>3}" if event.node is not None else "  -"
        self._out.write(f"{clock(event.time)}  {node}  {event.kind:<17} {event.text}\n")

    def close(self) -> None:
        self._out.flush()


class CsvWriter:
    def __init__(self, out: TextIO) -> None:
        self._out = out
        self._csv = csv.writer(out)
        self._csv.writerow(COLUMNS)

    def write(self, event: Event) -> None:
        self._csv.writerow(["" if v is None else v for v in (getattr(event, c) for c in COLUMNS)])

    def close(self) -> None:
        self._out.flush()


class JsonLinesWriter:
    def __init__(self, out: TextIO) -> None:
        self._out = out

    def write(self, event: Event) -> None:
        self._out.write(json.dumps(event.as_dict(), ensure_ascii=False) + "\n")

    def close(self) -> None:
        self._out.flush()


class ParquetWriter:
    """Columns buffered up to PARQUET_BATCH rows, then written as one row group."""

    def __init__(self, path: Path) -> None:
        import pyarrow as pa
        import pyarrow.parquet as pq

        self._pa = pa
        self.schema = pa.schema(
            [
                ("seq", pa.int64()),
                ("time", pa.float64()),
                ("frame", pa.int64()),
                ("kind", pa.string()),
                ("node", pa.int16()),
                ("text", pa.string()),
                ("index", pa.int32()),
                ("subindex", pa.int16()),
                ("code", pa.int64()),
                ("data", pa.string()),
                ("polling", pa.bool_()),
            ]
        )
        self._writer = pq.ParquetWriter(str(path), self.schema)
        self._columns: dict[str, list[Any]] = {c: [] for c in COLUMNS}

    def write(self, event: Event) -> None:
        columns = self._columns
        for name in COLUMNS:
            columns[name].append(getattr(event, name))
        if len(columns["seq"]) >= PARQUET_BATCH:
            self._flush()

    def _flush(self) -> None:
        if self._columns["seq"]:
            table = self._pa.table(self._columns, schema=self.schema)
            self._writer.write_table(table)
            self._columns = {c: [] for c in COLUMNS}

    def close(self) -> None:
        self._flush()
        self._writer.close()


def text_writer(fmt: ExportFormat, out: TextIO) -> EventWriter:
    """The writer for a text-stream format (every format but Parquet)."""
    if fmt is ExportFormat.CSV:
        return CsvWriter(out)
    if fmt is ExportFormat.JSON:
        return JsonLinesWriter(out)
    return TextWriter(out)


def write_all(writer: EventWriter, events: Iterable[Event]) -> int:
    count = 0
    for event in events:
        writer.write(event)
        count += 1
    writer.close()
    return count
