"""The wide CSV export, as a spreadsheet reads it: one row per time stamp, `time_s` and a column
per signal (named with its unit), empty cells where a signal has no sample, the TPDO signals of
one SYNC on one row. Read back with the csv module and checked against the capture's samples."""

from __future__ import annotations

import csv
import io
import itertools
import math
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pyarrow.parquet as pq
import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.models.scope import Capture, CaptureSignal, TriggerRequest
from servodesk.scope.samples import SamplesWriter
from servodesk.scope.wide import write_wide_csv
from servodesk.settings import Settings

POSITION, VELOCITY, IDENTITY = 0x6064, 0x606C, 0x1018


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path, scope_live_view=False)
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


def ok(response: httpx.Response) -> Any:
    assert response.status_code == 200, response.text
    return response.json()


def wait_done(client: TestClient, capture_id: int) -> dict[str, Any]:
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        capture: dict[str, Any] = ok(client.get(f"/api/scope/captures/{capture_id}"))
        if capture["state"] in ("done", "failed"):
            return capture
        time.sleep(0.1)
    raise AssertionError(f"capture {capture_id} did not finish")


def cells(text: str) -> tuple[list[str], list[list[str]]]:
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], rows[1:]


def test_wide_csv_has_a_column_per_signal_and_a_row_per_sync(client: TestClient) -> None:
    request = {
        "signals": [
            {"node": 1, "index": POSITION},
            {"node": 1, "index": VELOCITY},
            {"node": 2, "index": POSITION},
            {"node": 2, "index": IDENTITY, "subindex": 1},  # not mappable: polled by SDO
        ],
        "sync_period_us": 2000,
        "duration_s": 0.5,
    }
    capture = wait_done(client, ok(client.post("/api/scope/captures", json=request))["id"])
    assert capture["state"] == "done", capture
    url = f"/api/scope/captures/{capture['id']}/export"
    wide = client.get(url, params={"format": "csv", "layout": "wide"})
    assert wide.status_code == 200, wide.text
    assert f"servodesk-capture-{capture['id']}-wide.csv" in wide.headers["content-disposition"]
    long = pq.read_table(io.BytesIO(client.get(url, params={"format": "parquet"}).content))
    assert client.get(url, params={"format": "csv"}).text.startswith("time_s,timestamp,node,")

    header, rows = cells(wide.text)
    signals = capture["signals"]
    assert header[0] == "time_s"
    assert len(header) == 1 + len(signals)  # the 6041h state lanes were added too
    for name, signal in zip(header[1:], signals, strict=True):
        assert name.startswith(f"{signal['name']} · node {signal['node']} · ")
        if signal["unit"]:
            assert name.endswith(f"({signal['unit']})")
    times = [float(row[0]) for row in rows]
    assert all(b > a for a, b in itertools.pairwise(times))

    frame = long.to_pandas()
    for column, signal in enumerate(signals, start=1):
        mine = frame[
            (frame["node"] == signal["node"])
            & (frame["object"] == f"{signal['index']:04X}h:{signal['subindex']:02X}")
        ]
        filled = [
            (t, float(row[column])) for t, row in zip(times, rows, strict=True) if row[column]
        ]
        assert [v for _, v in filled] == mine["value"].tolist()  # every sample, exactly
        # each value on the row of its own time stamp (TPDO rows: the SYNC's first frame)
        assert all(t <= s for (t, _), s in zip(filled, mine["time_s"], strict=True))
        assert len(filled) == signal["samples"] > 10

    # the three TPDO signals answer the same SYNCs: they share rows
    pdo = [c for c, s in enumerate(signals, start=1) if s["source"] == "pdo"]
    pdo_rows = [row for row in rows if any(row[c] for c in pdo)]
    most = max(signals[c - 1]["samples"] for c in pdo)
    assert most <= len(pdo_rows) <= most + 2
    # the SDO-polled one has rows of its own
    sdo = next(c for c, s in enumerate(signals, start=1) if s["source"] == "sdo")
    assert all(not any(row[c] for c in pdo) for row in rows if row[sdo])

    refused = client.get(url, params={"format": "parquet", "layout": "wide"})
    assert refused.status_code == 422
    assert "CSV only" in refused.json()["message"]


def test_a_long_capture_is_merged_across_batches_and_sync_bursts(tmp_path: Path) -> None:
    """Two TPDO signals whose frames arrive up to 0.8 periods apart and a polled one, written
    in flush-sized chunks over several of the table's batches: one row per SYNC throughout."""
    period, syncs = 0.001, 70_000
    rng = np.random.default_rng(7)
    base = np.arange(syncs) * period
    first = base + rng.uniform(0, 0.0002, syncs)
    second = base + rng.uniform(0.0003, 0.0008, syncs)
    polled = np.arange(0, syncs * period, 0.0137) + 0.00005
    path = tmp_path / "samples.parquet"
    with SamplesWriter(path) as writer:
        for start in range(0, syncs, 33):  # a flush: every signal's chunk of ~33 ms
            end = start + 33
            writer.write(0, first[start:end], first[start:end], base[start:end], first[start:end])
            writer.write(1, second[start:end], second[start:end], -base[start:end], base[start:end])
            chunk = polled[(polled >= start * period) & (polled < end * period)]
            writer.write(2, chunk, chunk, chunk, chunk)
    capture = Capture(
        id=1,
        name=None,
        state="done",
        created=0.0,
        signals=[signal(0x6064, "pdo"), signal(0x6063, "pdo"), signal(0x2000, "sdo")],
        nodes=[1],
        sync_period_us=1000,
        duration_s=syncs * period,
        trigger=TriggerRequest(),
        samples=0,
        recording_id="wide-test",
    )
    out = write_wide_csv(capture, path, tmp_path / "wide.csv")
    header, rows = cells(out.read_text())
    assert len(header) == 4
    sync_rows = [row for row in rows if row[1]]
    assert len(sync_rows) == syncs
    assert all(row[2] and not row[3] for row in sync_rows)  # both TPDOs, never the polled one
    assert [float(row[0]) for row in sync_rows] == first.tolist()
    assert [float(row[2]) for row in sync_rows] == base.tolist()
    polled_rows = [row for row in rows if row[3]]
    assert [float(row[3]) for row in polled_rows] == polled.tolist()
    times = [float(row[0]) for row in rows]
    assert times == sorted(times)
    assert not any(math.isnan(t) for t in times)


def signal(index: int, source: str) -> CaptureSignal:
    return CaptureSignal(
        node=1,
        index=index,
        subindex=0,
        name=f"object {index:04X}h",
        key=f"o{index:04x}",
        source=source,  # type: ignore[arg-type]
        quantity="other",
        unit="",
        raw_unit="",
        scale=1.0,
        bits=32,
    )
