"""A capture's samples out as CSV, Parquet or MF4, streamed from its samples table.

CSV and Parquet have one row per sample (`COLUMNS`), in the table's order: each signal in time
order, signals interleaved in the chunks they were recorded in; the wide CSV layout (wide.py)
has one row per time stamp and a column per signal. Both are written one batch at a
time, so memory stays flat for any capture length. MF4 (ASAM MDF 4.10, asammdf) has one channel
group per signal with its own time master; asammdf extends its groups batch by batch through
its temporary file. Floats are written at full precision: every value reads back exactly.

Each file is written beside its target under a hidden temporary name and renamed at the end,
so a failed export never leaves a half file under the real name.
"""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Callable
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, Literal

import numpy as np
import numpy.typing as npt
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.csv as pacsv
import pyarrow.parquet as pq

from servodesk.errors import InvalidValueError, StateConflictError
from servodesk.models.scope import Capture, CaptureSignal, ExportFormat, ExportLayout
from servodesk.scope.samples import COMPRESSION, is_complete, read_samples, signal_groups
from servodesk.scope.wide import write_wide_csv

FileFormat = Literal["csv", "parquet", "mf4"]  # what export() writes (the .rrd is served as is)

COLUMNS = (
    "time_s",
    "timestamp",
    "node",
    "object",
    "name",
    "value",
    "unit",
    "raw",
    "raw_unit",
    "source",
)
EXPORT_SCHEMA = pa.schema(
    [
        pa.field("time_s", pa.float64(), False, {"unit": "s", "description": "from the trigger"}),
        pa.field("timestamp", pa.float64(), False, {"unit": "s", "description": "Unix epoch"}),
        pa.field("node", pa.int16(), False, {"description": "CANopen node id"}),
        pa.field("object", pa.string(), False, {"description": "index h:subindex (hex)"}),
        pa.field("name", pa.string(), False),
        pa.field(
            "value", pa.float64(), False, {"unit": "see column unit", "description": "raw × scale"}
        ),
        pa.field("unit", pa.string(), False),
        pa.field("raw", pa.float64(), False, {"unit": "see column raw_unit"}),
        pa.field("raw_unit", pa.string(), False),
        pa.field("source", pa.string(), False, {"description": "pdo or sdo"}),
    ]
)
SUFFIXES: dict[ExportFormat, str] = {"csv": "csv", "parquet": "parquet", "mf4": "mf4", "rrd": "rrd"}
CONTENT_TYPES: dict[ExportFormat, str] = {
    "csv": "text/csv; charset=utf-8",
    "parquet": "application/vnd.apache.parquet",
    "mf4": "application/octet-stream",  # MDF has no registered media type
    "rrd": "application/octet-stream",
}
_INT64_LIMIT = 2.0**63


def content_type(fmt: ExportFormat) -> str:
    return CONTENT_TYPES[fmt]


def filename(capture: Capture, fmt: ExportFormat, layout: ExportLayout = "long") -> str:
    """`servodesk-capture-12.csv` (`…-12-wide.csv`): the name a download gets."""
    wide = "-wide" if layout == "wide" else ""
    return f"servodesk-capture-{capture.id}{wide}.{SUFFIXES[fmt]}"


def object_label(signal: CaptureSignal) -> str:
    """`6064h:00`."""
    return f"{signal.index:04X}h:{signal.subindex:02X}"


def channel_name(signal: CaptureSignal) -> str:
    """`node2.position`: the MF4 channel of the signal's physical value."""
    return f"node{signal.node}.{signal.key}"


def export(
    capture: Capture, samples: Path, fmt: FileFormat, out: Path, layout: ExportLayout = "long"
) -> Path:
    """Write the capture's samples (`samples`: its table) as `fmt` to `out`, or into `out`
    under `filename()` when `out` is a directory; returns the file written. Blocking.
    StateConflictError (409) when the table was never finished (or never made)."""
    writers: dict[str, Callable[[Capture, Path, Path], Path]] = {
        "csv": write_wide_csv if layout == "wide" else _write_csv,
        "parquet": _write_parquet,
        "mf4": _write_mf4,
    }
    if fmt not in writers:
        raise ValueError(f"cannot export a capture as {fmt!r}")
    if layout == "wide" and fmt != "csv":
        raise InvalidValueError(f"the wide layout is for CSV only, not {fmt}: leave it out")
    if not is_complete(samples):  # ServoDesk stopped mid-capture: the table has no footer
        raise StateConflictError(
            "capture_samples_unavailable",
            f"capture {capture.id} has no finished samples table (ServoDesk stopped during it);"
            " its .rrd recording has what was recorded",
        )
    target = out / filename(capture, fmt, layout) if out.is_dir() else out
    # a name of its own: two downloads of the same export may run at once
    handle, name = tempfile.mkstemp(
        dir=target.parent, prefix=f".{target.stem}.", suffix=f".partial.{SUFFIXES[fmt]}"
    )
    os.close(handle)
    partial = Path(name)
    try:
        written = writers[fmt](capture, samples, partial)
        os.replace(written, target)
    finally:
        partial.unlink(missing_ok=True)
    return target


# ---------------------------------------------------------------------- rows (CSV, Parquet)


def _lookups(capture: Capture) -> dict[str, pa.Array]:
    """Per signal position, the columns that only depend on the signal."""
    signals = capture.signals
    return {
        "node": pa.array([s.node for s in signals], pa.int16()),
        "object": pa.array([object_label(s) for s in signals], pa.string()),
        "name": pa.array([s.name for s in signals], pa.string()),
        "unit": pa.array([s.unit for s in signals], pa.string()),
        "raw_unit": pa.array([s.raw_unit for s in signals], pa.string()),
        "source": pa.array([s.source for s in signals], pa.string()),
    }


def _rows(batch: pa.RecordBatch, lookups: dict[str, pa.Array]) -> pa.RecordBatch:
    positions = batch.column("signal")
    if len(positions) and pc.max(positions).as_py() >= len(lookups["node"]):
        raise ValueError("the samples table names a signal the capture does not have")
    own = {"time_s": "time", "timestamp": "timestamp", "value": "value", "raw": "raw"}
    arrays = [
        batch.column(own[name]) if name in own else pc.take(lookups[name], positions)
        for name in COLUMNS
    ]
    return pa.RecordBatch.from_arrays(arrays, schema=EXPORT_SCHEMA)


def _write_csv(capture: Capture, samples: Path, path: Path) -> Path:
    lookups = _lookups(capture)
    with path.open("wb") as file:
        # the header by hand: arrow would quote the names
        file.write((",".join(COLUMNS) + "\n").encode())
        # arrow writes floats in their shortest exact form (0.1, 5, 1700000000.25): read back
        # with a round-trip parser they are the same doubles; text fields are always quoted
        options = pacsv.WriteOptions(include_header=False, quoting_style="needed")
        with pacsv.CSVWriter(file, EXPORT_SCHEMA, write_options=options) as writer:
            for batch in read_samples(samples):
                writer.write_batch(_rows(batch, lookups))
    return path


def _units(capture: Capture) -> dict[str, dict[str, Any]]:
    return {
        channel_name(s): {
            "object": object_label(s),
            "name": s.name,
            "unit": s.unit,
            "raw_unit": s.raw_unit,
            "scale": s.scale,
        }
        for s in capture.signals
    }


def _write_parquet(capture: Capture, samples: Path, path: Path) -> Path:
    lookups = _lookups(capture)
    metadata = {
        "servodesk.capture": capture.model_dump_json(),
        "servodesk.units": json.dumps(_units(capture), ensure_ascii=False),
    }
    schema = EXPORT_SCHEMA.with_metadata(metadata)
    with pq.ParquetWriter(str(path), schema, compression=COMPRESSION) as writer:
        for batch in read_samples(samples):
            writer.write_batch(_rows(batch, lookups))  # one row group per batch
    return path


# ---------------------------------------------------------------------- MF4


def _integral_signals(capture: Capture, samples: Path) -> list[bool]:
    """Per signal, whether every raw value is a whole number in int64's range (its raw
    channel is then int64: MDF tools show bits and counts as integers)."""
    integral = [True] * len(capture.signals)
    for batch in read_samples(samples, columns=["signal", "raw"]):
        signal = batch.column("signal").to_numpy()
        raw = batch.column("raw").to_numpy()
        for position, rows in signal_groups(signal):
            if position < len(integral) and integral[position]:
                values = raw[rows]
                integral[position] = bool(
                    np.all(np.isfinite(values))
                    and np.all(np.trunc(values) == values)
                    and np.all(np.abs(values) < _INT64_LIMIT)
                )
    return integral


def _header_comment(capture: Capture) -> str:
    name = f" “{capture.name}”" if capture.name else ""
    nodes = ", ".join(str(n) for n in capture.nodes)
    return (
        f"ServoDesk scope capture {capture.id}{name}: {len(capture.signals)} signals of node(s) "
        f"{nodes}, SYNC {capture.sync_period_us} µs, trigger {capture.trigger.kind}; "
        "time_s is seconds from the trigger (the file's start time)"
    )


def _write_mf4(capture: Capture, samples: Path, path: Path) -> Path:
    from asammdf import MDF, Signal  # heavy (pandas): only when an MF4 is asked for

    integral = _integral_signals(capture, samples)
    empty: npt.NDArray[np.float64] = np.empty(0, dtype=np.float64)
    mdf = MDF(version="4.10")
    try:
        mdf.header.comment = _header_comment(capture)
        start = capture.trigger_time or capture.started or capture.created
        mdf.header.start_time = datetime.fromtimestamp(start, tz=UTC)
        groups: list[int] = []
        raw_types: list[type[np.generic]] = []
        seen: set[str] = set()
        for position, signal in enumerate(capture.signals):
            name = channel_name(signal)
            if name in seen:  # the same object twice: names must be unique in MDF tools
                name = f"{name}_{position}"
            seen.add(name)
            raw_type: type[np.generic] = np.int64 if integral[position] else np.float64
            raw_types.append(raw_type)
            comment = f"{object_label(signal)} {signal.name}"
            value = Signal(
                samples=empty,
                timestamps=empty,
                name=name,
                unit=signal.unit,
                comment=comment,
                master_metadata=("time_s", 1),  # 1: a time master (SYNC_TYPE_TIME)
            )
            raw = Signal(
                samples=np.empty(0, dtype=raw_type),
                timestamps=empty,
                name=f"{name}.raw",
                unit=signal.raw_unit,
                comment=f"{comment} (raw; value = raw × {signal.scale!r})",
            )
            index = mdf.append(
                [value, raw],
                acq_name=name,
                comment=f"{comment} ({signal.source})",
                common_timebase=True,
            )
            groups.append(len(groups) if index is None else index)
        for batch in read_samples(samples):
            columns = {n: batch.column(n).to_numpy() for n in ("signal", "time", "raw", "value")}
            for position, rows in signal_groups(columns["signal"]):
                if position >= len(groups):
                    raise ValueError("the samples table names a signal the capture does not have")
                mdf.extend(
                    groups[position],
                    [
                        (columns["time"][rows], None),
                        (columns["value"][rows], None),
                        (columns["raw"][rows].astype(raw_types[position]), None),
                    ],
                )
        return Path(mdf.save(path, overwrite=True))
    finally:
        mdf.close()
