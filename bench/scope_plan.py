"""The Scope page's waits, measured against the simulated drives over real HTTP: how long a plan
check takes (POST /api/scope/plan, what keeps "Start capture" disabled after each form change)
and how long from "Start capture" to the first sample recorded.

The app is served by uvicorn with its three simulated drives; beside it, the Drive page's
polling (GET /api/nodes/{n}/drive every 200 ms, each node) and the Network page's (nodes,
events, bus, loop lag every second) run from threads, as when those pages are open in other
tabs. Then ~20 plan checks of a changing form (signals of all three nodes added one by one,
SYNC period and trigger changed), and a few captures started and stopped.

Prints each figure as a ratio to its target (≤ 1.00 meets it) and exits 1 on a miss:
plan check p50 and max ≤ 1 s; start → first sample (the capture running) ≤ 1 s, worst of 3.
Not part of the test run. Run: `.venv/bin/python bench/scope_plan.py`.
"""

from __future__ import annotations

import statistics
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tests.live_server

from tests.live_server import serve_simulated

PLAN_TARGET_S = 1.0
START_TARGET_S = 1.0
CHECKS = 20
STARTS = 3
OBJECTS = (0x6064, 0x606C, 0x6077, 0x60F4)  # position, velocity, torque, following error


def polling(base: str, stop: threading.Event) -> list[threading.Thread]:
    def drive(node: int) -> None:
        with httpx.Client(base_url=base, headers={"X-Client-Id": f"bench-{node}"}) as client:
            while not stop.wait(0.2):
                client.get(f"/api/nodes/{node}/drive", timeout=10)

    def network() -> None:
        with httpx.Client(base_url=base) as client:
            while not stop.wait(1.0):
                for path in ("/api/nodes", "/api/events", "/api/bus", "/api/health/loop"):
                    client.get(path, timeout=10)

    threads = [threading.Thread(target=drive, args=(n,), daemon=True) for n in (1, 2, 3)]
    threads.append(threading.Thread(target=network, daemon=True))
    for thread in threads:
        thread.start()
    return threads


def form(step: int) -> dict[str, Any]:
    """The form after `step` changes: a signal more each time, other settings moving."""
    signals = [
        {"node": 1 + i % 3, "index": OBJECTS[(i // 3) % len(OBJECTS)]} for i in range(1 + step % 8)
    ]
    trigger: dict[str, Any] = {"kind": "none"}
    if step % 3 == 1:
        trigger = {"kind": "level", "node": 1, "index": 0x6064, "level": 1000 * step}
    elif step % 3 == 2:
        trigger = {"kind": "state", "node": 2, "state": "operation enabled"}
    return {
        "signals": signals,
        "sync_period_us": 1000 + 250 * (step % 4),
        "duration_s": 1.0 + step,
        "trigger": trigger,
    }


def plan_checks(client: httpx.Client) -> list[float]:
    times = []
    for step in range(CHECKS):
        began = time.perf_counter()
        answer = client.post("/api/scope/plan", json=form(step))
        times.append(time.perf_counter() - began)
        answer.raise_for_status()
    return times


def start_to_sample(client: httpx.Client) -> list[float]:
    times = []
    for step in range(STARTS):
        request = form(step * 3)  # free-running
        began = time.perf_counter()
        capture = client.post("/api/scope/captures", json=request)
        capture.raise_for_status()
        capture_id = capture.json()["id"]
        while True:
            now = client.get(f"/api/scope/captures/{capture_id}").json()
            if now["samples"] > 0 or now["state"] in ("done", "failed"):
                break
            time.sleep(0.005)
        times.append(time.perf_counter() - began)
        client.delete(f"/api/scope/captures/{capture_id}").raise_for_status()
    return times


def line(label: str, measured: float, target: float) -> bool:
    ratio = measured / target
    verdict = "ok" if ratio <= 1.0 else "MISSED"
    print(
        f"{label:<34} {measured * 1000:8.1f} ms  target ≤ {target * 1000:.0f} ms"
        f"  ratio {ratio:5.2f}  {verdict}"
    )
    return ratio <= 1.0


def main() -> int:
    with (
        tempfile.TemporaryDirectory() as data,
        serve_simulated(Path(data), static_dir=None, overrides={"scope_live_view": False}) as base,
    ):
        stop = threading.Event()
        threads = polling(base, stop)
        try:
            with httpx.Client(base_url=base, timeout=60) as client:
                time.sleep(1.0)  # the pollers under way
                checks = plan_checks(client)
                starts = start_to_sample(client)
        finally:
            stop.set()
            for thread in threads:
                thread.join(timeout=5)
    print(f"{CHECKS} plan checks of a changing form, {STARTS} starts; Drive/Network polling beside")
    results = [
        line("plan check p50", statistics.median(checks), PLAN_TARGET_S),
        line("plan check max", max(checks), PLAN_TARGET_S),
        line("plan check first (nothing cached)", checks[0], PLAN_TARGET_S),
        line("start → first sample, worst", max(starts), START_TARGET_S),
    ]
    return 0 if all(results) else 1


if __name__ == "__main__":
    sys.exit(main())
