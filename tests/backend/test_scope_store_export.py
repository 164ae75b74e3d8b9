"""The scope's capture store, samples table and exports: what goes in comes back out exactly.

Samples of four signals (an integer position, a negative velocity, a float, a statusword) are
written across several row groups, exported as CSV, Parquet and MF4 and read back with pandas,
pyarrow and asammdf: the same values, times, units and object labels. The store keeps its
records across a reopen and marks captures an earlier run left running as failed. A 2-million
row table exports with bounded memory (measured in a child process).
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import textwrap
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd  # type: ignore[import-untyped]  # no pandas-stubs in the dev tools
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from asammdf import MDF

import servodesk
from servodesk.api.errors import describe
from servodesk.errors import CaptureNotFoundError, StateConflictError
from servodesk.models.scope import Capture, CaptureSignal, CaptureState, TriggerRequest
from servodesk.scope.export import COLUMNS, FileFormat, content_type, export, filename
from servodesk.scope.samples import (
    ROW_GROUP_ROWS,
    SAMPLES_SCHEMA,
    SamplesWriter,
    is_complete,
    read_samples,
)
from servodesk.scope.store import INTERRUPTED, UNREADABLE_SAMPLES, CaptureStore

TRIGGER_TIME = 1_700_000_000.125
PER_SIGNAL = 50_000  # 4 signals: 200 000 rows, three full row groups and a tail
CHUNK = 7_919  # rows per write: a prime, so chunks straddle the row groups


def signal(
    place: tuple[int, int, int], name: str, units: tuple[str, str], scale: float, **more: Any
) -> CaptureSignal:
    """A signal at (node, index, subindex) with (unit, raw unit); its key is its name's first
    word."""
    key = name.split()[0].lower()
    fields: dict[str, Any] = {"name": name, "key": key, "quantity": key, "source": "pdo"}
    fields |= dict(zip(("node", "index", "subindex"), place, strict=True))
    fields |= dict(zip(("unit", "raw_unit"), units, strict=True))
    return CaptureSignal.model_validate(fields | {"scale": scale, "bits": 32} | more)


SIGNALS = [
    signal((2, 0x6064, 0), "Position actual value", ("rev", "inc"), 2.0**-17, tpdo=1),
    signal((2, 0x606C, 0), "Velocity actual value", ("rpm", "inc/s"), 60 / 131072, tpdo=1),
    signal((3, 0x2001, 0x1A), "Temperature of the drive", ("°C", "°C"), 1.0, source="sdo"),
    signal((3, 0x6041, 0), "Statusword", ("", ""), 1.0, bits=16, tpdo=2),
]


def make_capture(
    capture_id: int = 12, state: CaptureState = "done", signals: list[CaptureSignal] | None = None
) -> Capture:
    return Capture(
        id=capture_id,
        name="Tuning, run 3",
        state=state,
        created=TRIGGER_TIME - 2,
        started=TRIGGER_TIME - 1,
        trigger_time=TRIGGER_TIME,
        ended=TRIGGER_TIME + 50 if state == "done" else None,
        signals=SIGNALS if signals is None else signals,
        nodes=[2, 3],
        sync_period_us=1000,
        duration_s=51.0,
        trigger=TriggerRequest(kind="bit", node=3, bit=10, pre_s=1.0),
        samples=4 * PER_SIGNAL,
        recording_id="0f8d1c2a-5b7e-4c3d-9a10-1234567890ab",
    )


def raw_values(signal: int, n: np.ndarray) -> np.ndarray:
    """Per signal: an integer position, a negative velocity, a float (float32 like a REAL32
    object), a statusword."""
    if signal == 0:
        return (n * 977 - 2_000_000_000).astype(np.float64)
    if signal == 1:
        return -(n % 50_000 + 1).astype(np.float64) * 3
    if signal == 2:
        return (36.6 + np.sin(n / 100.0)).astype(np.float32).astype(np.float64)
    return np.where(n % 2 == 0, 0x1237, 0x0637).astype(np.float64)


def write_samples(path: Path, per_signal: int = PER_SIGNAL) -> pd.DataFrame:
    """Write the four signals interleaved in chunks (as the flush thread does); returns the rows
    as the samples table should hold them, in order."""
    expected: list[pd.DataFrame] = []
    with SamplesWriter(path) as writer:
        for start in range(0, per_signal, CHUNK):
            n = np.arange(start, min(start + CHUNK, per_signal))
            for position, signal in enumerate(SIGNALS):
                time = (n - 1000) * 1e-3 + position * 1e-4  # 1 s before the trigger
                timestamp = TRIGGER_TIME + time + 0.000_37
                raw = raw_values(position, n)
                value = raw * signal.scale
                writer.write(position, time, timestamp, raw, value)
                expected.append(
                    pd.DataFrame(
                        {"signal": position, "time": time, "timestamp": timestamp}
                        | {"raw": raw, "value": value}
                    )
                )
        assert writer.rows == per_signal * len(SIGNALS)
    return pd.concat(expected, ignore_index=True)


@pytest.fixture(scope="module")
def samples(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, pd.DataFrame]:
    path = tmp_path_factory.mktemp("capture") / "samples.parquet"
    return path, write_samples(path)


def expected_rows(table: pd.DataFrame) -> pd.DataFrame:
    """The export's rows for `table` (the samples), built independently of the exporter."""
    labels: dict[str, list[Any]] = {
        "node": [s.node for s in SIGNALS],
        "object": ["6064h:00", "606Ch:00", "2001h:1A", "6041h:00"],
        "name": [s.name for s in SIGNALS],
        "unit": [s.unit for s in SIGNALS],
        "raw_unit": [s.raw_unit for s in SIGNALS],
        "source": [s.source for s in SIGNALS],
    }
    rows: dict[str, Any] = {"time_s": table["time"], "timestamp": table["timestamp"]}
    for column, per_signal in labels.items():
        rows[column] = table["signal"].map(dict(enumerate(per_signal)))
    rows |= {"value": table["value"], "raw": table["raw"]}
    return pd.DataFrame(rows)[list(COLUMNS)]


def assert_rows_equal(got: pd.DataFrame, want: pd.DataFrame) -> None:
    assert list(got.columns) == list(COLUMNS)
    assert len(got) == len(want)
    for column in COLUMNS:
        if want[column].dtype.kind == "f":
            # exactly the same doubles, not merely close
            assert np.array_equal(got[column].to_numpy(np.float64), want[column].to_numpy()), column
        else:
            assert got[column].astype(str).tolist() == want[column].astype(str).tolist(), column


# ---------------------------------------------------------------------- the samples table


def test_samples_are_written_in_row_groups_and_read_back_in_batches(
    samples: tuple[Path, pd.DataFrame],
) -> None:
    path, expected = samples
    meta = pq.ParquetFile(path).metadata
    assert meta.num_rows == len(expected) == 200_000
    sizes = [meta.row_group(i).num_rows for i in range(meta.num_row_groups)]
    assert sizes == [ROW_GROUP_ROWS] * 3 + [200_000 - 3 * ROW_GROUP_ROWS]
    assert pq.read_schema(path).remove_metadata().equals(SAMPLES_SCHEMA.remove_metadata())
    assert is_complete(path)

    batches = list(read_samples(path))
    assert all(b.num_rows <= ROW_GROUP_ROWS for b in batches)
    got = pa.Table.from_batches(batches).to_pandas()
    pd.testing.assert_frame_equal(got, expected, check_dtype=False, check_exact=True)
    assert got["signal"].dtype == np.int32


def test_writer_copies_refuses_and_closes_once(tmp_path: Path) -> None:
    path, buffer = tmp_path / "s.parquet", np.array([1.0, 2.0, 3.0])
    writer = SamplesWriter(path)
    writer.write(0, buffer, buffer, buffer, buffer)
    buffer[:] = -1.0  # a ring buffer reused at once: the table keeps what was written
    with pytest.raises(ValueError, match="length"):
        writer.write(0, np.zeros(3), np.zeros(3), np.zeros(2), np.zeros(3))
    writer.close()
    writer.close()  # idempotent
    with pytest.raises(RuntimeError, match="closed"):
        writer.write(0, buffer, buffer, buffer, buffer)
    assert pq.read_table(path)["raw"].to_pylist() == [1.0, 2.0, 3.0]


def test_an_unclosed_table_is_not_complete(tmp_path: Path) -> None:
    path, ones = tmp_path / "s.parquet", np.ones(ROW_GROUP_ROWS + 10)
    writer = SamplesWriter(path)
    writer.write(0, ones, ones, ones, ones)
    assert path.exists()
    assert not is_complete(path)  # a killed process: row groups without the footer
    writer.close()
    assert is_complete(path)
    assert pq.ParquetFile(path).metadata.num_rows == ROW_GROUP_ROWS + 10


# ---------------------------------------------------------------------- exports, read back


def read_csv(path: Path) -> pd.DataFrame:
    text = {c: str for c in ("object", "name", "unit", "raw_unit", "source")}
    # pandas 3 parses floats exactly by default (earlier versions need float_precision)
    return pd.read_csv(path, dtype=text, keep_default_na=False)


def read_parquet(path: Path) -> pd.DataFrame:
    table = pq.read_table(path)
    types = {f.name: f.type for f in table.schema}
    assert types["node"] == pa.int16()
    assert types["object"] == pa.string()
    assert types["time_s"] == types["value"] == types["raw"] == pa.float64()
    metadata = table.schema.metadata
    assert Capture.model_validate_json(metadata[b"servodesk.capture"]) == make_capture()
    units = json.loads(metadata[b"servodesk.units"])
    assert units["node2.velocity"] == {
        "object": "606Ch:00",
        "name": "Velocity actual value",
        "unit": "rpm",
        "raw_unit": "inc/s",
        "scale": 60 / 131072,
    }
    assert table.schema.field("time_s").metadata[b"unit"] == b"s"
    return table.to_pandas()


ROW_READERS: dict[str, Callable[[Path], pd.DataFrame]] = {"csv": read_csv, "parquet": read_parquet}


@pytest.mark.parametrize("fmt", ["csv", "parquet"])
def test_row_exports_read_back_identical(
    fmt: FileFormat, samples: tuple[Path, pd.DataFrame], tmp_path: Path
) -> None:
    path, expected = samples
    written = export(make_capture(), path, fmt, tmp_path)
    assert written == tmp_path / f"servodesk-capture-12.{fmt}"
    assert sorted(p.name for p in tmp_path.iterdir()) == [written.name]  # no partial left
    assert_rows_equal(ROW_READERS[fmt](written), expected_rows(expected))


def test_csv_text_is_plain_and_exact(samples: tuple[Path, pd.DataFrame], tmp_path: Path) -> None:
    out = export(make_capture(), samples[0], "csv", tmp_path / "named.csv")
    assert out == tmp_path / "named.csv"
    with out.open(encoding="utf-8") as file:
        header, first = file.readline(), file.readline()
        lines = list(file)
    assert header == "time_s,timestamp,node,object,name,value,unit,raw,raw_unit,source\n"
    assert first.startswith("-1,")
    # integral raw values are integers; the statusword's empty unit is an empty text
    assert first.split(",")[7] == "-2000000000"
    statusword = next(line for line in lines if "6041h:00" in line)
    assert next(line for line in lines if '"°C"' in line)  # UTF-8 units
    assert statusword.rstrip("\n").split(",")[-4:] == ['""', "4663", '""', '"pdo"']


def test_mf4_reads_back_in_mdf_tools(samples: tuple[Path, pd.DataFrame], tmp_path: Path) -> None:
    path, expected = samples
    out = export(make_capture(), path, "mf4", tmp_path)
    assert out.name == "servodesk-capture-12.mf4"
    mdf = MDF(out)
    try:
        assert mdf.version == "4.10"
        assert "ServoDesk scope capture 12" in mdf.header.comment
        assert "Tuning, run 3" in mdf.header.comment
        assert mdf.header.start_time == datetime.fromtimestamp(TRIGGER_TIME, tz=UTC)
        assert len(mdf.groups) == len(SIGNALS)
        for position, signal in enumerate(SIGNALS):
            want = expected[expected["signal"] == position]
            name = f"node{signal.node}.{signal.key}"
            value, raw = mdf.get(name), mdf.get(f"{name}.raw")
            assert value.unit == signal.unit
            assert raw.unit == signal.raw_unit
            assert value.comment.startswith(expected_rows(want)["object"].iloc[0])
            assert signal.name in value.comment
            assert np.array_equal(value.timestamps, want["time"].to_numpy())
            assert np.array_equal(raw.timestamps, want["time"].to_numpy())
            assert np.array_equal(value.samples, want["value"].to_numpy())
            assert np.array_equal(raw.samples, want["raw"].to_numpy())
            # whole raw values are integer channels; the float one stays float
            assert raw.samples.dtype.kind == ("f" if position == 2 else "i")
            group = mdf.groups[position]
            assert group.channels[0].name == "time_s"
            assert group.channels[0].unit == "s"
    finally:
        mdf.close()


@pytest.mark.parametrize("fmt", ["csv", "parquet", "mf4"])
def test_an_empty_capture_exports(fmt: FileFormat, tmp_path: Path) -> None:
    path = tmp_path / "samples.parquet"
    SamplesWriter(path).close()  # nothing recorded: still a table with the schema
    assert pq.read_schema(path).remove_metadata().equals(SAMPLES_SCHEMA.remove_metadata())
    out = export(make_capture(), path, fmt, tmp_path)
    if fmt == "csv":
        assert out.read_text(encoding="utf-8") == ",".join(COLUMNS) + "\n"
    elif fmt == "parquet":
        assert pq.read_table(out).num_rows == 0
    else:
        with MDF(out) as mdf:
            assert len(mdf.get("node2.position").samples) == 0


def test_a_failed_export_leaves_no_file(tmp_path: Path) -> None:
    path = tmp_path / "samples.parquet"
    with SamplesWriter(path) as writer:
        writer.write(7, np.zeros(2), np.zeros(2), np.zeros(2), np.zeros(2))  # no signal 7
    formats: tuple[FileFormat, ...] = ("csv", "parquet", "mf4")
    for fmt in formats:
        with pytest.raises(ValueError, match="signal"):
            export(make_capture(), path, fmt, tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["samples.parquet"]


@pytest.mark.parametrize("fmt", ["csv", "parquet", "mf4"])
@pytest.mark.parametrize("rows", [0, ROW_GROUP_ROWS])
def test_an_unfinished_table_is_a_conflict(fmt: FileFormat, rows: int, tmp_path: Path) -> None:
    path, ones = tmp_path / "samples.parquet", np.ones(rows)
    writer = SamplesWriter(path)  # kept: arrow would write the footer when it is collected
    writer.write(0, ones, ones, ones, ones)  # never closed; 0 rows: no file at all
    with pytest.raises(StateConflictError) as caught:
        export(make_capture(), path, fmt, tmp_path)
    assert describe(caught.value)[0] == 409
    assert sorted(p.name for p in tmp_path.iterdir()) == (["samples.parquet"] if rows else [])
    assert writer.rows == rows


def test_simultaneous_exports_of_one_file(
    samples: tuple[Path, pd.DataFrame], tmp_path: Path
) -> None:
    with ThreadPoolExecutor(3) as pool:  # raises what an export raised
        list(pool.map(lambda _: export(make_capture(), samples[0], "csv", tmp_path), range(3)))
    assert [p.name for p in tmp_path.iterdir()] == ["servodesk-capture-12.csv"]
    assert_rows_equal(read_csv(tmp_path / "servodesk-capture-12.csv"), expected_rows(samples[1]))


@pytest.mark.parametrize(
    ("fmt", "name", "media"),
    [
        ("csv", "servodesk-capture-12.csv", "text/csv; charset=utf-8"),
        ("parquet", "servodesk-capture-12.parquet", "application/vnd.apache.parquet"),
        ("mf4", "servodesk-capture-12.mf4", "application/octet-stream"),
        ("rrd", "servodesk-capture-12.rrd", "application/octet-stream"),
    ],
)
def test_download_names_and_types(fmt: Any, name: str, media: str) -> None:
    assert filename(make_capture(), fmt) == name
    assert content_type(fmt) == media


# ---------------------------------------------------------------------- the store


@pytest.fixture
def store(tmp_path: Path) -> Iterator[CaptureStore]:
    captures = CaptureStore(tmp_path / "scope")
    captures.open()
    yield captures
    captures.close()


def builder(state: CaptureState = "done") -> Callable[[int], Capture]:
    return lambda capture_id: make_capture(capture_id, state)


def test_store_keeps_captures_across_a_reopen(tmp_path: Path) -> None:
    root = tmp_path / "scope"
    store = CaptureStore(root)
    assert store.open() == []
    first, second, third = (store.create(builder()) for _ in range(3))
    assert [first.id, second.id, third.id] == [1, 2, 3]
    store.save(second.model_copy(update={"name": "renamed", "samples": 5}))
    store.samples_path(second.id).write_bytes(b"x" * 100)
    store.rrd_path(second.id).write_bytes(b"y" * 23)
    assert store.size_bytes(second.id) == 123
    assert store.directory(second.id) == root / "2"
    assert store.rrd_path(2) == root / "2" / "capture.rrd"
    assert store.samples_path(2) == root / "2" / "samples.parquet"
    assert store.path == root / "captures.sqlite"
    assert store.size_bytes(99) == 0
    store.close()

    reopened = CaptureStore(root)
    assert reopened.open() == []
    try:
        assert reopened.get(second.id).name == "renamed"
        assert reopened.get(first.id) == first
        assert [c.id for c in reopened.list()] == [3, 2, 1]  # newest first
        reopened.delete(second.id)
        assert not (root / "2").exists()
        with pytest.raises(CaptureNotFoundError):
            reopened.get(second.id)
        with pytest.raises(CaptureNotFoundError):
            reopened.delete(second.id)
        # ids are never given twice, not even the newest deleted one
        reopened.delete(third.id)
        assert reopened.create(builder()).id == 4
    finally:
        reopened.close()


def test_unknown_captures_answer_404(store: CaptureStore) -> None:
    with pytest.raises(CaptureNotFoundError) as caught:
        store.get(42)
    with pytest.raises(CaptureNotFoundError):
        store.save(make_capture(42))
    status, body = describe(caught.value)
    assert (status, body.error) == (404, "capture_not_found")


def test_a_failed_build_reserves_nothing(store: CaptureStore) -> None:
    def broken(capture_id: int) -> Capture:
        raise ValueError("no such node")

    with pytest.raises(ValueError, match="no such node"):
        store.create(broken)
    assert store.list() == []
    assert store.create(builder()).id == 1


def test_concurrent_creates_get_distinct_ids(store: CaptureStore) -> None:
    with ThreadPoolExecutor(4) as pool:
        ids = list(pool.map(lambda _: store.create(builder()).id, range(40)))
    assert sorted(ids) == list(range(1, 41))


def test_interrupted_captures_are_marked_failed_on_open(tmp_path: Path) -> None:
    root = tmp_path / "scope"
    store = CaptureStore(root)
    store.open()
    armed, running, done = (store.create(builder(s)) for s in ("armed", "running", "done"))
    writer = SamplesWriter(store.samples_path(running.id))
    ones = np.ones(ROW_GROUP_ROWS)
    writer.write(0, ones, ones, ones, ones)  # ServoDesk is killed: the writer never closes
    store.rrd_path(running.id).write_bytes(b"r" * 1000)
    store.close()

    reopened = CaptureStore(root)
    assert reopened.open() == [armed.id, running.id]
    try:
        for capture_id in (armed.id, running.id):
            capture = reopened.get(capture_id)
            assert capture.state == "failed"
            assert capture.error == INTERRUPTED
            assert capture.ended is not None
        failed = reopened.get(running.id)
        assert failed.size_bytes == reopened.size_bytes(running.id) > 1000
        assert UNREADABLE_SAMPLES in failed.notes
        assert reopened.get(done.id) == done
        assert reopened.open() == []  # already open: nothing more to do
    finally:
        reopened.close()
    again = CaptureStore(root)
    assert again.open() == []  # marked once
    again.close()


def test_store_refuses_use_before_open(tmp_path: Path) -> None:
    with pytest.raises(RuntimeError, match="not open"):
        CaptureStore(tmp_path).list()


# ---------------------------------------------------------------------- bounded memory

MEMORY_PROBE = textwrap.dedent(
    """
    import json, sys, tracemalloc
    from pathlib import Path
    import numpy as np
    import pyarrow as pa
    import pyarrow.parquet as pq
    from servodesk.scope.export import export
    from servodesk.scope.samples import SamplesWriter
    from tests.backend.test_scope_store_export import make_capture

    folder, rows = Path(sys.argv[1]), int(sys.argv[2])
    pool = pa.default_memory_pool()
    capture = make_capture()
    warm = folder / "warm.parquet"  # the first export imports lazily: not part of the peak
    with SamplesWriter(warm) as w:
        w.write(0, np.zeros(10), np.zeros(10), np.zeros(10), np.zeros(10))
    export(capture, warm, "csv", folder / "warm.csv")
    tracemalloc.start()
    path = folder / "samples.parquet"
    chunk = 5000
    with SamplesWriter(path) as writer:
        for start in range(0, rows // 4, chunk):
            n = np.arange(start, start + chunk, dtype=np.float64)
            for signal in range(4):
                writer.write(signal, n * 1e-3, n * 1e-3 + 1.7e9, n - 1e6, (n - 1e6) / 8)
    write_python = tracemalloc.get_traced_memory()[1]
    write_arrow = pool.max_memory()
    tracemalloc.reset_peak()
    before = tracemalloc.get_traced_memory()[0]
    out = export(capture, path, "csv", folder / "big.csv")
    export_python = tracemalloc.get_traced_memory()[1] - before
    lines = 0
    with out.open("rb") as file:
        for block in iter(lambda: file.read(1 << 20), b""):
            lines += block.count(b"\\n")
    groups = pq.ParquetFile(path).metadata.num_row_groups
    export_arrow = pool.max_memory()
    print(json.dumps({k: v for k, v in locals().items() if isinstance(v, int)}))
    """
)


def test_a_long_capture_exports_with_bounded_memory(tmp_path: Path) -> None:
    rows = 2_000_000
    # the whole table would take 36 B a row in arrow (72 MB), its CSV text over 200 MB
    bound = 48 * 2**20
    repo = Path(servodesk.__file__).parent.parent.parent
    env = os.environ | {"PYTHONPATH": os.pathsep.join(p for p in sys.path if p)}
    result = subprocess.run(
        [sys.executable, "-c", MEMORY_PROBE, str(tmp_path), str(rows)],
        capture_output=True,
        text=True,
        env=env,
        cwd=repo,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    probe = json.loads(result.stdout.splitlines()[-1])
    assert probe["lines"] == rows + 1
    assert probe["groups"] == math.ceil(rows / ROW_GROUP_ROWS)
    assert probe["write_python"] < bound, probe
    assert probe["write_arrow"] < bound, probe
    assert probe["export_python"] < 16 * 2**20, probe
    assert probe["export_arrow"] < bound, probe
