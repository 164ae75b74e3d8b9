"""The statusword's lanes and the cursors' readout on a capture of the simulated drives: an
enable during the capture shows in the .rrd (read back with rerun's own reader) as the CiA 402
states and bits the samples hold, and the measure route reads the same samples."""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from fastapi.testclient import TestClient
from rerun.chunk import RrdReader

from servodesk.app import create_app
from servodesk.settings import Settings
from servodesk_protocol.cia402 import decode_state
from tests.backend.test_scope_capture import CLIENT, ok, samples_of, signal_rows, wait_done

STATUSWORD = 0x6041


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path, scope_live_view=False)
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


def lanes_in(rrd: Path, under: str) -> dict[str, list[str]]:
    """Every StateChange lane under `under`: entity name → its values in time order."""
    found: dict[str, list[tuple[int, str]]] = {}
    for chunk in RrdReader(rrd).stream():
        path = chunk.entity_path
        if chunk.is_static or not path.startswith(under + "/"):
            continue
        batch = chunk.to_record_batch()
        if "StateChange:state" not in batch.schema.names:
            continue
        times = batch.column("time").cast("int64").to_pylist()
        states = [v[0] for v in batch.column("StateChange:state").to_pylist()]
        name = path[len(under) + 1 :].replace("\\ ", " ")
        found.setdefault(name, []).extend(zip(times, states, strict=True))
    return {name: [s for _, s in sorted(rows)] for name, rows in found.items()}


def changes(values: list[str]) -> list[str]:
    return [v for i, v in enumerate(values) if i == 0 or values[i - 1] != v]


def test_an_enable_shows_as_state_and_bit_lanes_matching_the_samples(
    client: TestClient, tmp_path: Path
) -> None:
    request = {
        "signals": [{"node": 1, "index": STATUSWORD}],
        "duration_s": 1.5,
        "lanes": {"statusword_bits": [10, 3]},
    }
    capture = ok(client.post("/api/scope/captures", json=request))
    assert capture["lanes"]["statusword_bits"] == [3, 10]
    deadline = time.monotonic() + 5
    while ok(client.get(f"/api/scope/captures/{capture['id']}"))["samples"] < 50:
        assert time.monotonic() < deadline, "no samples"
        time.sleep(0.05)
    ok(client.post("/api/nodes/1/drive/enable", headers=CLIENT))
    done = wait_done(client, capture["id"])
    assert done["state"] == "done", done

    rrd = tmp_path / "capture.rrd"
    url = f"/api/scope/captures/{capture['id']}/export"
    rrd.write_bytes(client.get(url, params={"format": "rrd"}).content)
    lanes = lanes_in(rrd, "/drives/1/statusword")
    assert set(lanes) == {"state", "bit_03 fault", "bit_10 target reached"}  # as chosen

    raw = signal_rows(samples_of(client, capture["id"]), 1, STATUSWORD)["raw"].astype(int)
    words = raw.tolist()
    expected_states = changes([decode_state(w).name.replace("_", " ").capitalize() for w in words])
    assert lanes["state"] == expected_states
    assert lanes["state"][0] == "Switch on disabled"
    assert lanes["state"][-1] == "Operation enabled"  # the enable, step by step
    for bit in (3, 10):
        key = "bit_03 fault" if bit == 3 else "bit_10 target reached"
        assert lanes[key] == changes([str(w >> bit & 1) for w in words])
    assert lanes["bit_03 fault"] == ["0"]

    # the cursors: A before the enable, B at the end — the statusword's own samples
    times = signal_rows(samples_of(client, capture["id"]), 1, STATUSWORD)["time_s"].to_numpy()
    t0, t1 = float(times[10]), float(times[-1])
    readout = ok(client.get(f"/api/scope/captures/{capture['id']}/measure?t0={t0}&t1={t1}"))
    [row] = readout["signals"]
    assert readout["dt"] == pytest.approx(t1 - t0)
    assert row["at_a"] == words[10]
    assert row["at_b"] == words[-1]
    assert row["delta"] == words[-1] - words[10]
    assert row["count"] == len(words) - 10
    assert row["min"] == min(words[10:])
    assert row["max"] == max(words[10:])
    assert row["mean"] == pytest.approx(np.mean(words[10:]))

    answer = client.get(f"/api/scope/captures/{capture['id']}/measure?t0=99&t1={t1}")
    assert answer.status_code == 422
    assert "t0 = 99 s lies outside the capture: pick a time from" in answer.json()["message"]
    overview = ok(client.get(f"/api/scope/captures/{capture['id']}/trace?signal=0&points=50"))
    assert len(overview["times"]) <= 50
    assert max(overview["high"]) == max(words)


def test_a_request_without_lanes_gets_the_default_bits(client: TestClient) -> None:
    request = {"signals": [{"node": 1, "index": STATUSWORD}], "duration_s": 0.2}
    capture = wait_done(client, ok(client.post("/api/scope/captures", json=request))["id"])
    assert capture["lanes"]["statusword_bits"] == [3, 7, 10, 11, 12, 13]
    bad = {**request, "lanes": {"statusword_bits": [16]}}
    assert client.post("/api/scope/plan", json=bad).status_code == 422
