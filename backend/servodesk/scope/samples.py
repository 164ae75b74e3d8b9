"""A capture's canonical sample table (`samples.parquet`), written while the capture runs.

One row per sample of one signal: `signal` (its position in Capture.signals), `time` (s from the
trigger, negative before it), `timestamp` (epoch s of the frame's arrival), `raw` (the object's
value as read; 32-bit integers are exact in float64) and `value` (raw × the signal's scale).
Rows are buffered and written as Parquet row groups of ROW_GROUP_ROWS, so a long capture never
holds more than one group in memory; the exports read it back batch by batch (`read_samples`).

The Parquet footer is written by `close()`: a table whose writer never closed (ServoDesk killed
mid-capture) cannot be read (`is_complete` tells).
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from pathlib import Path
from types import TracebackType
from typing import Any

import numpy as np
import numpy.typing as npt
import pyarrow as pa
import pyarrow.parquet as pq

ROW_GROUP_ROWS = 65_536  # rows per row group, and per batch when reading
COMPRESSION = "zstd"
_MAGIC = b"PAR1"

SAMPLES_SCHEMA = pa.schema(
    [
        pa.field("signal", pa.int32(), nullable=False),
        pa.field("time", pa.float64(), nullable=False),
        pa.field("timestamp", pa.float64(), nullable=False),
        pa.field("raw", pa.float64(), nullable=False),
        pa.field("value", pa.float64(), nullable=False),
    ],
    metadata={"time": "s from the trigger", "timestamp": "s since the Unix epoch"},
)
_FLOAT_COLUMNS = ("time", "timestamp", "raw", "value")


class SamplesWriter:
    """Appends samples to `path`; one flush thread writes (not thread-safe by design)."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self._writer: Any = None  # pq.ParquetWriter, opened by the first row group
        self._buffer: dict[str, list[npt.NDArray[Any]]] = {c: [] for c in SAMPLES_SCHEMA.names}
        self._buffered = 0
        self._rows = 0
        self._closed = False

    @property
    def rows(self) -> int:
        """Rows accepted so far (written or still buffered)."""
        return self._rows

    @property
    def closed(self) -> bool:
        return self._closed

    def write(
        self,
        signal: int,
        time: npt.ArrayLike,
        timestamp: npt.ArrayLike,
        raw: npt.ArrayLike,
        value: npt.ArrayLike,
    ) -> None:
        """Add samples of one signal (arrays of one length). They are copied: the caller may
        reuse its buffers at once."""
        if self._closed:
            raise RuntimeError(f"{self.path.name}: the samples table is closed")
        if signal < 0:
            raise ValueError(f"signal position {signal} is negative")
        columns = [
            np.array(a, dtype=np.float64, copy=True).ravel() for a in (time, timestamp, raw, value)
        ]
        n = len(columns[0])
        if any(len(c) != n for c in columns):
            raise ValueError("time, timestamp, raw and value differ in length")
        if n == 0:
            return
        self._buffer["signal"].append(np.full(n, signal, dtype=np.int32))
        for name, column in zip(_FLOAT_COLUMNS, columns, strict=True):
            self._buffer[name].append(column)
        self._buffered += n
        self._rows += n
        if self._buffered >= ROW_GROUP_ROWS:
            self._flush(whole_groups_only=True)

    def _flush(self, *, whole_groups_only: bool) -> None:
        if self._buffered == 0:
            return
        merged = {name: np.concatenate(parts) for name, parts in self._buffer.items()}
        cut = (
            (self._buffered // ROW_GROUP_ROWS) * ROW_GROUP_ROWS
            if whole_groups_only
            else self._buffered
        )
        if cut:
            writer = self._open()
            for start in range(0, cut, ROW_GROUP_ROWS):
                stop = min(start + ROW_GROUP_ROWS, cut)
                arrays = [pa.array(merged[name][start:stop]) for name in SAMPLES_SCHEMA.names]
                writer.write_table(pa.Table.from_arrays(arrays, schema=SAMPLES_SCHEMA))
        # the tail (less than a group) waits for more rows; copied so the merge can be freed
        self._buffer = {name: [merged[name][cut:].copy()] for name in SAMPLES_SCHEMA.names}
        self._buffered -= cut

    def _open(self) -> Any:
        if self._writer is None:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._writer = pq.ParquetWriter(str(self.path), SAMPLES_SCHEMA, compression=COMPRESSION)
        return self._writer

    def close(self) -> None:
        """Write what is buffered and the footer; an empty table still gets a file (with the
        schema) so exports work. Idempotent."""
        if self._closed:
            return
        self._closed = True
        try:
            self._flush(whole_groups_only=False)
            self._open()
        finally:
            if self._writer is not None:
                self._writer.close()
            self._buffer = {c: [] for c in SAMPLES_SCHEMA.names}
            self._buffered = 0

    def __enter__(self) -> SamplesWriter:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()


def is_complete(path: Path) -> bool:
    """Whether `path` is a finished Parquet file (its writer closed: the footer is there)."""
    try:
        with path.open("rb") as file:
            if file.read(4) != _MAGIC:
                return False
            file.seek(-4, 2)
            return file.read(4) == _MAGIC
    except OSError:
        return False


def read_samples(
    path: Path,
    *,
    columns: Sequence[str] | None = None,
    batch_size: int = ROW_GROUP_ROWS,
) -> Iterator[pa.RecordBatch]:
    """The table's rows in batches of at most `batch_size`, in the order they were written
    (per signal in time order; signals interleaved); all columns unless `columns` is given."""
    file = pq.ParquetFile(str(path))
    try:
        yield from file.iter_batches(
            batch_size=batch_size, columns=list(columns) if columns is not None else None
        )
    finally:
        file.close()


def signal_groups(signal: npt.NDArray[np.int32]) -> Iterator[tuple[int, npt.NDArray[np.intp]]]:
    """(position, row indices) of each signal present in a batch's `signal` column, rows kept in
    their order."""
    if len(signal) == 0:
        return
    order = np.argsort(signal, kind="stable")
    positions, starts = np.unique(signal[order], return_index=True)
    for position, rows in zip(positions.tolist(), np.split(order, starts[1:]), strict=True):
        yield int(position), rows


def value_batches(
    path: Path,
) -> Iterator[tuple[npt.NDArray[np.int32], npt.NDArray[np.float64], npt.NDArray[np.float64]]]:
    """(signal, time, value) columns batch by batch: what the cursors' readout reads."""
    for batch in read_samples(path, columns=("signal", "time", "value")):
        yield (
            batch.column(0).to_numpy().astype(np.int32, copy=False),
            batch.column(1).to_numpy().astype(np.float64, copy=False),
            batch.column(2).to_numpy().astype(np.float64, copy=False),
        )
