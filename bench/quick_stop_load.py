"""Quick stop under load, for bench/jog_stop.py: from the request to the controlword on the bus.

A quick stop of node 3 is sent over REST (`POST /api/nodes/3/drive/quick-stop`) and over the
live channel (`{"type": "quick_stop", "node": 3}`) while the app is idle and while it does the
work that used to hold a stop back: a large vendor EDS uploaded and parsed for node 3, a scope
capture (5 signals at 1 kHz, polled like the Scope page), an upload-all of node 3's dictionary
and a large CAN log decode. Each kind of work runs in a process of its own (its HTTP traffic
and file making do not share this process's interpreter lock with the frame listener), and
`hogs` CPU-bound processes run beside the server for the loaded figures.
"""

from __future__ import annotations

import json
import multiprocessing
import random
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from contextlib import ExitStack, contextmanager
from multiprocessing.synchronize import Event as EventType
from pathlib import Path
from typing import Any, Protocol

import can
import httpx
from websockets.sync.client import connect as ws_connect

NODE = 3
TARGET_MS = 30.0
CONTROLWORD = 0x6040
EDS_SIZE = int(7.9 * 1024 * 1024)  # under the 8 MB upload cap
SCOPE_SIGNALS = [
    {"node": 1, "index": 0x6064},  # Position actual value
    {"node": 1, "index": 0x606C},  # Velocity actual value
    {"node": 2, "index": 0x6064},
    {"node": 2, "index": 0x606C},
    {"node": 3, "index": 0x6064},
]
CONDITIONS = ("idle", "eds-upload", "scope", "upload-all", "log-decode")


class FrameSource(Protocol):
    def first_after(
        self, since: float, match: Callable[[can.Message], bool], timeout: float = 3.0
    ) -> float: ...


def is_quick_stop(msg: can.Message) -> bool:
    """An SDO expedited write of controlword 0002h (quick stop, bits 0–2 and 7 = 010b) to 6040h
    of node 3."""
    data = bytes(msg.data)
    if msg.arbitration_id != 0x600 + NODE or len(data) < 6 or data[0] & 0xE0 != 0x20:
        return False
    if int.from_bytes(data[1:3], "little") != CONTROLWORD:
        return False
    return int.from_bytes(data[4:6], "little") & 0x87 == 0x02


# ---------------------------------------------------------------------- work beside the stops


def _eds_uploads(base: str, stop: EventType) -> None:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from tests.large_eds import make_eds

    eds = make_eds(EDS_SIZE)
    with httpx.Client(base_url=base, timeout=120) as http:
        while not stop.is_set():
            http.post(f"/api/nodes/{NODE}/od", files={"file": ("vendor.eds", eds)})
        http.delete(f"/api/nodes/{NODE}/od")


def _scope(base: str, stop: EventType, duration_s: float = 600) -> None:
    body = {"signals": SCOPE_SIGNALS, "sync_period_us": 1000, "duration_s": duration_s}
    with httpx.Client(base_url=base, timeout=30) as http:
        capture: dict[str, Any] | None = None
        while capture is None and not stop.is_set():
            response = http.post("/api/scope/captures", json=body)
            if response.status_code == 200:
                capture = response.json()
            else:
                time.sleep(0.5)
        while not stop.wait(0.25):  # the Scope page's poll
            if capture is not None:
                http.get(f"/api/scope/captures/{capture['id']}")
        if capture is not None:
            http.delete(f"/api/scope/captures/{capture['id']}")


def _upload_all(base: str, stop: EventType) -> None:
    with httpx.Client(base_url=base, timeout=30) as http:
        job = http.post(f"/api/nodes/{NODE}/upload-all").json()
        while not stop.wait(0.1):
            if http.get(f"/api/jobs/{job['id']}?since=999999").json()["state"] != "running":
                job = http.post(f"/api/nodes/{NODE}/upload-all").json()
        http.delete(f"/api/jobs/{job['id']}")


def _log_decodes(base: str, stop: EventType, frames: int) -> None:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
    from bench.log_decode import write_candump

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "site.log"
        write_candump(path, frames)
        data = path.read_bytes()
    with httpx.Client(base_url=base, timeout=300) as http:
        while not stop.is_set():
            http.post("/api/logs/decode", files={"file": ("site.log", data)})


WORK: dict[str, Callable[..., None]] = {
    "eds-upload": _eds_uploads,
    "scope": _scope,
    "upload-all": _upload_all,
    "log-decode": _log_decodes,
}
WARM_UP_S = {"eds-upload": 4.0, "scope": 3.0, "upload-all": 1.0, "log-decode": 8.0}


@contextmanager
def beside(condition: str, base: str, log_frames: int) -> Iterator[None]:
    """The condition's work running in its own process while the block runs."""
    if condition == "idle":
        yield
        return
    extra: tuple[Any, ...] = (log_frames,) if condition == "log-decode" else ()
    with work_process(WORK[condition], base, extra, WARM_UP_S[condition]):
        yield


@contextmanager
def work_process(
    target: Callable[..., None], base: str, extra: tuple[Any, ...], warm_up: float
) -> Iterator[None]:
    """`target(base, stop, *extra)` in a process of its own, `warm_up` s before the block runs
    and until it ends (then `stop` is set)."""
    context = multiprocessing.get_context("spawn")
    stop = context.Event()
    worker = context.Process(target=target, args=(base, stop, *extra), daemon=True)
    worker.start()
    try:
        time.sleep(warm_up)  # until the work is under way
        yield
    finally:
        stop.set()
        worker.join(60)
        if worker.is_alive():
            worker.kill()
            worker.join()


@contextmanager
def cpu_hogs(count: int) -> Iterator[None]:
    """`count` processes spinning on a core each, beside the server."""
    hogs = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(count)]
    try:
        yield
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()


# ---------------------------------------------------------------------- trials


def rest_trials(base: str, ear: FrameSource, count: int) -> list[float]:
    """Each stop on a connection of its own, as `curl -X POST` sends it: the request's bytes are
    made before the clock starts. An HTTP library here would spend its own milliseconds in this
    process, whose listener thread holds the interpreter lock for every frame on the bus (a
    1 kHz capture's), and its waits for that lock were counted against the server."""
    host, port = base.removeprefix("http://").split(":")
    path = f"/api/nodes/{NODE}/drive/quick-stop"
    request = (
        f"POST {path} HTTP/1.1\r\nHost: {host}:{port}\r\nContent-Length: 0\r\n"
        "Connection: close\r\n\r\n"
    ).encode()
    values: list[float] = []
    for _ in range(count):
        time.sleep(random.uniform(0.02, 0.08))  # spread over the background work's phases
        sent = time.monotonic()
        with socket.create_connection((host, int(port)), timeout=30) as sock:
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            sock.sendall(request)
            answer = b""
            while chunk := sock.recv(65536):
                answer += chunk
        status = answer.split(b" ", 2)[1] if answer.startswith(b"HTTP/") else b"none"
        if status != b"200":
            raise RuntimeError(f"quick stop answered {status.decode()}: {answer[-300:]!r}")
        values.append((ear.first_after(sent, is_quick_stop, timeout=10) - sent) * 1000)
    return values


def ws_trials(base: str, ear: FrameSource, count: int) -> list[float]:
    """As a page sends it. The channel answers nothing to a quick stop; a ping after it is
    answered once the stop was handled, so each trial starts, as over REST, when the previous
    one is done (the channel handles a socket's messages one after the other)."""
    values: list[float] = []
    url = base.replace("http://", "ws://") + "/api/ws"
    with ws_connect(url, max_size=None) as ws:
        message = f'{{"type": "quick_stop", "node": {NODE}}}'
        for _ in range(count):
            time.sleep(random.uniform(0.02, 0.08))
            sent = time.monotonic()
            ws.send(message)
            values.append((ear.first_after(sent, is_quick_stop, timeout=10) - sent) * 1000)
            ws.send('{"type": "ping"}')
            while json.loads(ws.recv(timeout=30)).get("type") != "pong":
                pass
    return values


def quick_stop_trials(
    base: str,
    ear: FrameSource,
    *,
    trials: int,
    hogs: int,
    conditions: tuple[str, ...],
    log_frames: int,
    report: Callable[[str, list[float], float], bool],
) -> bool:
    """Every condition, REST then WebSocket; True when every p99 is within the target."""
    met = True
    load = f"{hogs} CPU hogs beside the server" if hogs else "no CPU hogs"
    print(f"(d) quick stop -> controlword 0002h on the bus ({load}):")
    with ExitStack() as stack:
        stack.enter_context(cpu_hogs(hogs))
        for condition in conditions:
            with beside(condition, base, log_frames):
                rest = rest_trials(base, ear, trials)
                ws = ws_trials(base, ear, trials)
                lag = httpx.get(f"{base}/api/health", timeout=30).json().get("loop")
            met &= report(f"    {condition:<10} REST", rest, TARGET_MS)
            met &= report(f"    {condition:<10} WS  ", ws, TARGET_MS)
            if lag is not None:  # a server from before the loop watch has none
                print(
                    f"    {condition:<10} the server's event loop lag over the last minute: p50 "
                    f"{lag['p50_ms']} ms, p99 {lag['p99_ms']} ms, max {lag['max_ms']} ms"
                )
    return met
