"""A capture's samples as a wide CSV: one row per time stamp, `time_s` then one column per
signal (physical value, named as the Scope page names it, with its unit), empty cells where a
signal has no sample at that time.

TPDO signals answering the same SYNC share a row: their frames arrive one after the other in a
burst after each SYNC (on a bus at most 100 % loaded the burst fits in one SYNC period), so a
row takes TPDO samples, in time order, until a signal it already has comes again or a period has
passed since its first; its time is that first sample's. An SDO-polled signal is read at its own
times: its samples get rows of their own.

The samples table holds each signal in time order, signals interleaved in the chunks they were
recorded in. The rows are merged batch by batch: samples are held only until every signal still
to come has reached their time, so memory stays bounded by how far apart the signals were
written, not by the capture's length.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pyarrow as pa
import pyarrow.csv as pacsv

from servodesk.models.scope import Capture, CaptureSignal
from servodesk.scope.samples import read_samples

Floats = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int64]
_EMPTY_F: Floats = np.empty(0, dtype=np.float64)
_EMPTY_I: Ints = np.empty(0, dtype=np.int64)


def column_name(signal: CaptureSignal) -> str:
    """`Position actual value · node 1 · 6064h:00 (rev)`: the Scope page's name of the signal,
    its node and object, and its unit."""
    name = f"{signal.name} · node {signal.node} · {signal.index:04X}h:{signal.subindex:02X}"
    return f"{name} ({signal.unit})" if signal.unit else name


def header(capture: Capture) -> str:
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerow(
        ["time_s", *(column_name(s) for s in capture.signals)]
    )
    return out.getvalue()


@dataclass
class _Pending:
    """Samples read but not written yet, as arrays (time, signal, value)."""

    times: list[Floats] = field(default_factory=list)
    signals: list[Ints] = field(default_factory=list)
    values: list[Floats] = field(default_factory=list)

    def add(self, times: Floats, signals: Ints, values: Floats) -> None:
        self.times.append(times)
        self.signals.append(signals)
        self.values.append(values)

    def take(self) -> tuple[Floats, Ints, Floats]:
        """Everything held, in time order (per time: signal order); the holder is emptied."""
        times = np.concatenate(self.times) if self.times else _EMPTY_F
        signals = np.concatenate(self.signals) if self.signals else _EMPTY_I
        values = np.concatenate(self.values) if self.values else _EMPTY_F
        self.times, self.signals, self.values = [], [], []
        order = np.lexsort((signals, times))
        return times[order], signals[order], values[order]


def assign_rows(
    times: Sequence[float], signals: Sequence[int], pdo: Sequence[bool], period_s: float
) -> tuple[list[int], int]:
    """Row number per sample (samples in time order), and the first sample of the last TPDO
    row, which more samples may still join (len(times) when there is none)."""
    rows: list[int] = []
    row = -1
    start = -np.inf  # the current TPDO row's first time
    seen: set[int] = set()
    pdo_row = -1
    last_open = len(times)
    sdo_rows: dict[float, tuple[int, set[int]]] = {}  # SDO samples at one exact time share
    for i, (t, s) in enumerate(zip(times, signals, strict=True)):
        if pdo[s]:
            if pdo_row < 0 or s in seen or t - start >= period_s:
                row += 1
                pdo_row, start, seen = row, t, set()
                last_open = i
            seen.add(s)
            rows.append(pdo_row)
        else:
            shared = sdo_rows.get(t)
            if shared is None or s in shared[1]:
                row += 1
                shared = (row, set())
                sdo_rows = {t: shared}
            shared[1].add(s)
            rows.append(shared[0])
    return rows, last_open


def wide_batches(capture: Capture, samples: Path) -> Iterator[pa.RecordBatch]:
    """The wide rows, batch by batch, in time order."""
    count = len(capture.signals)
    pdo = [s.source == "pdo" for s in capture.signals]
    period_s = capture.sync_period_us / 1e6
    remaining = np.zeros(count, dtype=np.int64)  # samples of each signal still to come
    for batch in read_samples(samples, columns=["signal"]):
        found = batch.column(0).to_numpy().astype(np.int64)
        if found.size and int(found.max()) >= count:
            raise ValueError("the samples table names a signal the capture does not have")
        remaining += np.bincount(found, minlength=count)
    newest = np.full(count, -np.inf)  # the latest time read of each signal
    pending = _Pending()
    for batch in read_samples(samples, columns=["signal", "time", "value"]):
        signals = batch.column(0).to_numpy().astype(np.int64)
        times = batch.column(1).to_numpy().astype(np.float64)
        values = batch.column(2).to_numpy().astype(np.float64)
        pending.add(times, signals, values)
        remaining -= np.bincount(signals, minlength=count)
        for position in np.unique(signals):
            newest[position] = times[signals == position].max()
        to_come = remaining > 0
        # a signal still to come sends nothing older than what it sent last
        horizon = float(newest[to_come].min()) if to_come.any() else np.inf
        out = _rows(pending, horizon, pdo, period_s, count)
        if out is not None:
            yield out
    out = _rows(pending, np.inf, pdo, period_s, count)
    if out is not None:
        yield out


def _rows(
    pending: _Pending, horizon: float, pdo: Sequence[bool], period_s: float, count: int
) -> pa.RecordBatch | None:
    """The rows complete before `horizon` (all of them at the end: inf); the rest stays
    pending, from the last TPDO row on (a later sample may still join it)."""
    times, signals, values = pending.take()
    ready = None if horizon == np.inf else int(np.searchsorted(times, horizon, side="left"))
    rows, last_open = assign_rows(times[:ready].tolist(), signals[:ready].tolist(), pdo, period_s)
    cut = len(rows) if ready is None else min(last_open, len(rows))
    if cut < times.size:
        pending.add(times[cut:], signals[cut:], values[cut:])
    if cut == 0:
        return None
    row_of = np.asarray(rows[:cut], dtype=np.int64)
    row_of -= row_of.min()
    height = int(row_of.max()) + 1
    grid = np.zeros((height, count), dtype=np.float64)
    filled = np.zeros((height, count), dtype=bool)
    grid[row_of, signals[:cut]] = values[:cut]
    filled[row_of, signals[:cut]] = True
    row_time = np.full(height, np.inf)
    np.minimum.at(row_time, row_of, times[:cut])
    order = np.argsort(row_time, kind="stable")
    arrays = [pa.array(row_time[order])]
    arrays += [pa.array(grid[order, j], mask=~filled[order, j]) for j in range(count)]
    names = ["time_s", *(f"s{j}" for j in range(count))]
    return pa.RecordBatch.from_arrays(arrays, names=names)


def write_wide_csv(capture: Capture, samples: Path, path: Path) -> Path:
    with path.open("wb") as file:
        file.write(header(capture).encode())  # by hand: arrow would name columns its way
        options = pacsv.WriteOptions(include_header=False, quoting_style="needed")
        schema = pa.schema(
            [pa.field("time_s", pa.float64())]
            + [pa.field(f"s{j}", pa.float64()) for j in range(len(capture.signals))]
        )
        with pacsv.CSVWriter(file, schema, write_options=options) as writer:
            for batch in wide_batches(capture, samples):
                writer.write_batch(batch)
    return path
