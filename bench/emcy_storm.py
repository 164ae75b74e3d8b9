"""An EMCY storm against the fault read route: 1000 EMCY frames/s for 10 s from simulated node 1
while a client reads `GET /api/nodes/1/faults` back to back. Prints p50/p99/max of the read and
the p99's ratio to the 200 ms target, then whether every EMCY reached the history (and how
many were dropped: the target is none).

The app runs in this process (uvicorn on 127.0.0.1 in a thread), so the client shares its
interpreter: a pessimistic setting. Run: `.venv/bin/python bench/emcy_storm.py`.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import threading
import time
from pathlib import Path

import httpx
import uvicorn

from servodesk.app import create_app
from servodesk.services import Services
from servodesk.settings import Settings
from servodesk_sim.frames import Frame

TARGET_P99_MS = 200.0


def pace(services: Services, rate: int, seconds: float, sent: list[int]) -> None:
    sim = services.bus.sim
    assert sim is not None
    start = time.perf_counter()
    total = int(rate * seconds)
    for i in range(total):
        due = start + i / rate
        delay = due - time.perf_counter()
        if delay > 0:
            time.sleep(delay)
        sim.inject(Frame(0x081, bytes([4 if i % 2 else 1, 0])))
        sent[0] += 1


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rate", type=int, default=1000, help="EMCY frames per second")
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--port", type=int, default=8791)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as data:
        settings = Settings(simulated=True, port=args.port, data_dir=Path(data))
        app = create_app(settings, static_dir=None)
        server = uvicorn.Server(
            uvicorn.Config(app, host="127.0.0.1", port=args.port, log_level="warning")
        )
        thread = threading.Thread(target=server.run, daemon=True)
        thread.start()
        while not server.started:
            time.sleep(0.05)
        services: Services = app.state.services
        base = f"http://127.0.0.1:{args.port}"
        latencies: list[float] = []
        sent = [0]
        storm = threading.Thread(target=pace, args=(services, args.rate, args.seconds, sent))
        with httpx.Client(base_url=base, timeout=10) as client:
            storm.start()
            while storm.is_alive():
                started = time.perf_counter()
                answer = client.get("/api/nodes/1/faults?limit=50")
                latencies.append((time.perf_counter() - started) * 1000)
                answer.raise_for_status()
            storm.join()
            total = 0
            deadline = time.monotonic() + 30
            while total < sent[0] and time.monotonic() < deadline:
                total = client.get("/api/nodes/1/faults?limit=1").json()["total"]
                time.sleep(0.1)
        server.should_exit = True
        thread.join(timeout=20)
    latencies.sort()
    p99 = latencies[min(len(latencies) - 1, int(len(latencies) * 0.99))]
    print(f"EMCY storm: {sent[0]} frames at {args.rate}/s, {len(latencies)} reads during it")
    print(
        f"GET /api/nodes/1/faults: p50 {statistics.median(latencies):.1f} ms, "
        f"p99 {p99:.1f} ms, max {latencies[-1]:.1f} ms; p99 / target {TARGET_P99_MS:.0f} ms = "
        f"{p99 / TARGET_P99_MS:.2f} ({'ok' if p99 <= TARGET_P99_MS else 'OVER'})"
    )
    dropped = services.events.dropped + services.storage.dropped
    print(f"history: {total} of {sent[0]} EMCYs stored, {dropped} dropped")


if __name__ == "__main__":
    main()
