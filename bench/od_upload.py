"""Uploading a large dictionary must not freeze the server or leave its memory behind.

Starts `servodesk serve --sim` in its own process on a free loopback port, generates a valid
7.9 MB EDS (under the 8 MB upload cap: the CiA 402 drive's EDS plus generated records), then:

- polls `GET /api/health` every 10 ms while one upload is parsed, and while three run at once,
  and prints the latency p50 / p99 / max (target: p99 < 100 ms);
- reads the server's resident memory (VmRSS) at start, after three concurrent uploads to nodes
  1–3, and after `DELETE /api/nodes/{n}/od` of all three (target: < 1.5x the start).

Run: `make bench` or `.venv/bin/python bench/od_upload.py`.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository, for tests/
from tests.large_eds import make_eds  # the same generator the tests use
from tests.live_server import free_port

SIZE = int(7.9 * 1024 * 1024)
HEALTH_P99_TARGET_MS = 100.0
RSS_TARGET = 1.5


@contextmanager
def server(port: int, extra_env: dict[str, str]) -> Iterator[subprocess.Popen[bytes]]:
    data_dir = tempfile.mkdtemp(prefix="servodesk-bench-")
    command = [sys.executable, "-m", "servodesk.cli", "serve", "--sim", "--port", str(port)]
    process = subprocess.Popen(
        command,
        env={"SERVODESK_DATA_DIR": data_dir, "PATH": "/usr/bin:/bin", **extra_env},
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        deadline = time.monotonic() + 30
        while True:
            try:
                nodes = httpx.get(f"http://127.0.0.1:{port}/api/nodes", timeout=1).json()
                if len(nodes) == 3:
                    break
            except httpx.HTTPError:
                pass
            if time.monotonic() > deadline or process.poll() is not None:
                raise SystemExit("the server did not start")
            time.sleep(0.1)
        yield process
    finally:
        process.terminate()
        process.wait(timeout=20)


def rss_mb(pid: int) -> float:
    status = Path(f"/proc/{pid}/status").read_text()
    kb = int(status.split("VmRSS:")[1].split()[0])
    return kb / 1024


def upload(base: str, node: int, eds: bytes) -> float:
    start = time.perf_counter()
    response = httpx.post(
        f"{base}/api/nodes/{node}/od", files={"file": ("big.eds", eds)}, timeout=120
    )
    response.raise_for_status()
    return time.perf_counter() - start


def health_during(base: str, work: list[threading.Thread]) -> list[float]:
    """Health latencies (ms), polled every 10 ms while the `work` threads run."""
    latencies: list[float] = []
    with httpx.Client(base_url=base, timeout=30) as client:
        for thread in work:
            thread.start()
        while any(thread.is_alive() for thread in work):
            start = time.perf_counter()
            client.get("/api/health").raise_for_status()
            latencies.append((time.perf_counter() - start) * 1000)
            time.sleep(0.01)
    for thread in work:
        thread.join()
    return latencies


def report(label: str, latencies: list[float]) -> float:
    ordered = sorted(latencies)
    p99 = ordered[min(len(ordered) - 1, round(0.99 * (len(ordered) - 1)))]
    print(
        f"health during {label}: p50 {statistics.median(ordered):.1f} ms, p99 {p99:.1f} ms, "
        f"max {ordered[-1]:.1f} ms over {len(ordered)} requests "
        f"(target p99 < {HEALTH_P99_TARGET_MS:g} ms, ratio {p99 / HEALTH_P99_TARGET_MS:.2f})"
    )
    return p99


def main() -> int:
    # VAR=value arguments go to the server's environment (e.g. PYTHONMALLOC=pymalloc to compare
    # CPython's own allocator with the C library's, which `servodesk serve` uses by default)
    extra_env = dict(arg.split("=", 1) for arg in sys.argv[1:] if "=" in arg)
    eds = make_eds(SIZE)
    print(f"generated EDS: {len(eds) / 1024 / 1024:.1f} MB")
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    with server(port, extra_env) as process:
        time.sleep(1.0)  # let start-up settle before the baseline
        start_rss = rss_mb(process.pid)
        seconds: list[float] = []

        def one(node: int) -> threading.Thread:
            return threading.Thread(target=lambda: seconds.append(upload(base, node, eds)))

        single = report("one 7.9 MB parse", health_during(base, [one(1)]))
        print(f"one upload took {seconds[0]:.1f} s")
        httpx.delete(f"{base}/api/nodes/1/od").raise_for_status()
        triple = report("three 7.9 MB parses", health_during(base, [one(n) for n in (1, 2, 3)]))
        loaded_rss = rss_mb(process.pid)
        for node in (1, 2, 3):
            httpx.delete(f"{base}/api/nodes/{node}/od", timeout=60).raise_for_status()
        time.sleep(0.5)
        end_rss = rss_mb(process.pid)
    ratio = end_rss / start_rss
    print(
        f"server RSS: start {start_rss:.0f} MB, with three 7.9 MB dictionaries {loaded_rss:.0f} "
        f"MB, after deleting them {end_rss:.0f} MB = {ratio:.2f}x the start "
        f"(target < {RSS_TARGET:g}x, ratio {ratio / RSS_TARGET:.2f})"
    )
    met = single < HEALTH_P99_TARGET_MS and triple < HEALTH_P99_TARGET_MS and ratio < RSS_TARGET
    print("targets met" if met else "targets NOT met")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
