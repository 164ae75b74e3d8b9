"""Hostile inputs: bodies and files made to exhaust the server's memory or disk are refused
without either growing, and without stalling the event loop.

Starts `servodesk serve --sim` in its own process on a free loopback port (its data directory
and TMPDIR in a temporary directory of their own), measures its idle RSS, then sends, one at
a time:

- a BLF zlib bomb to POST /api/logs/decode: a valid file header, then LOG_CONTAINER objects each
  declaring 128 kB and expanding to 200 MB of zeros, the first object inside claiming 4 GB
  (4 containers: 0.8 MB on the wire);
- a 100 MB JSON value to PUT /api/nodes/3/sdo/6081/0;
- 33 MB of PDOs to POST /api/nodes/1/pdos/validate;
- a 300 MB log to POST /api/logs/decode (over the 256 MB limit), with a Content-Length and
  chunked (no length).

Each is sent on a raw socket, stopping as soon as the server answers. Printed for each: the
answer, how much of the body the server took, the peak RSS of the server process against
2× its idle RSS (target ≤ 1.00 of that), of its child processes (log decoding runs there),
the peak bytes spooled to its temporary and data directories, and the event loop's lag: the
slowest GET /api/health answered every 20 ms meanwhile (target ≤ 100 ms). Exits 1 on a miss.

Not part of the test run. Run: `make bench` or `.venv/bin/python bench/hostile_inputs.py`.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import select
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import httpx
import psutil  # type: ignore[import-untyped]  # no stubs installed; dev dependency

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository, for tests/
from tests.blf_bombs import zlib_bomb  # the same bomb the tests send, bigger

MB = 1024 * 1024
RSS_TARGET = 2.0  # peak server RSS / idle RSS
LAG_TARGET_MS = 100.0
CHUNK = 1024 * 1024
BIN = Path(sys.executable).parent
Body = Callable[[], Iterator[bytes]]


@dataclass
class Attack:
    name: str
    method: str
    path: str
    content_type: str
    body: Body
    length: int | None  # declared Content-Length; None: chunked


@dataclass
class Outcome:
    status: int
    message: str
    sent: int
    rss_mb: float
    children_mb: float
    spooled_mb: float
    lag_ms: float


# ---------------------------------------------------------------------- the bodies


def repeated(head: bytes, filler: bytes, tail: bytes, total: int) -> Body:
    """`head`, then `filler` repeated, then `tail`: `total` bytes, made a megabyte at a time."""

    def chunks() -> Iterator[bytes]:
        yield head
        left = total - len(head) - len(tail)
        block = filler * (CHUNK // len(filler))
        while left > 0:
            piece = block[: min(left, len(block))]
            left -= len(piece)
            yield piece
        yield tail

    return chunks


def form(name: str, content: Body, size: int) -> tuple[Body, int]:
    """A multipart form with the one file part `content` of `size` bytes."""
    head = (
        f'--bench\r\nContent-Disposition: form-data; name="file"; filename="{name}"\r\n'
        "Content-Type: application/octet-stream\r\n\r\n"
    ).encode()
    tail = b"\r\n--bench--\r\n"

    def chunks() -> Iterator[bytes]:
        yield head
        yield from content()
        yield tail

    return chunks, len(head) + size + len(tail)


def pdo_set(size: int) -> bytes:
    mapping = [{"index": 0x6041, "subindex": 0, "bits": 16}] * 4
    pdo = {
        "kind": "tpdo",
        "number": 1,
        "cob_id": 0x181,
        "valid": True,
        "transmission_type": 1,
        "mapping": mapping,
    }
    one = json.dumps(pdo).encode()
    count = size // (len(one) + 1)
    return b'{"pdos": [' + b",".join([one] * count) + b"]}"


def attacks(args: argparse.Namespace) -> list[Attack]:
    bomb = zlib_bomb(args.bomb_mb * MB, args.bomb_containers)
    print(
        f"BLF bomb: {len(bomb) / MB:.2f} MB, {args.bomb_containers} containers of 128 kB "
        f"declared, {args.bomb_mb} MB each expanded"
    )
    bomb_body, bomb_size = form("bomb.blf", lambda: iter([bomb]), len(bomb))
    line = b"(1700000000.000000) can0 181#0102030405060708\n"
    log = repeated(b"", line, b"", args.upload_mb * MB)
    upload, upload_size = form("big.log", log, args.upload_mb * MB)
    value = repeated(b'{"value": "', b"A", b'"}', args.json_mb * MB)
    pdos = pdo_set(args.pdos_mb * MB)
    multipart = "multipart/form-data; boundary=bench"
    return [
        # no body at all: the noise floor of the figures on this machine
        Attack(
            "control: a 1 kB SDO write",
            "PUT",
            "/api/nodes/3/sdo/6081/0",
            "application/json",
            repeated(b'{"value": 100', b" ", b"}", 1024),
            1024,
        ),
        Attack("BLF zlib bomb", "POST", "/api/logs/decode", multipart, bomb_body, bomb_size),
        Attack(
            f"{args.json_mb} MB JSON SDO write",
            "PUT",
            "/api/nodes/3/sdo/6081/0",
            "application/json",
            value,
            args.json_mb * MB,
        ),
        Attack(
            f"{len(pdos) / MB:.0f} MB of PDOs",
            "POST",
            "/api/nodes/1/pdos/validate",
            "application/json",
            lambda: iter([pdos]),
            len(pdos),
        ),
        Attack(
            f"{args.upload_mb} MB log, Content-Length",
            "POST",
            "/api/logs/decode",
            multipart,
            upload,
            upload_size,
        ),
        Attack(
            f"{args.upload_mb} MB log, chunked", "POST", "/api/logs/decode", multipart, upload, None
        ),
    ]


# ---------------------------------------------------------------------- sending


def send(port: int, attack: Attack) -> tuple[int, str, int]:
    """(status, error message, body bytes sent): the body goes until the server answers."""
    head = [
        f"{attack.method} {attack.path} HTTP/1.1",
        f"Host: 127.0.0.1:{port}",
        f"Content-Type: {attack.content_type}",
        "Connection: close",
    ]
    head.append(
        f"Content-Length: {attack.length}"
        if attack.length is not None
        else "Transfer-Encoding: chunked"
    )
    with socket.create_connection(("127.0.0.1", port), timeout=120) as sock:
        sock.sendall(("\r\n".join(head) + "\r\n\r\n").encode())
        sent = [0]
        with contextlib.suppress(BrokenPipeError, ConnectionResetError):
            send_body(sock, attack, sent)  # until the end, its answer, or it closes
        answer = read_answer(sock)
    status_line, _, rest = answer.partition(b"\r\n")
    status = int(status_line.split()[1]) if status_line else 0
    body = rest.partition(b"\r\n\r\n")[2]
    try:
        message = str(json.loads(body).get("message", ""))
    except ValueError:
        message = body[:200].decode(errors="replace")
    return status, message, sent[0]


def send_body(sock: socket.socket, attack: Attack, sent: list[int]) -> None:
    """The body, until the server answers; `sent[0]` counts the bytes that went."""
    for chunk in attack.body():
        for at in range(0, len(chunk), CHUNK):
            if select.select([sock], [], [], 0)[0]:
                return  # it answered: the rest is not wanted
            piece = chunk[at : at + CHUNK]
            if attack.length is None:  # chunked transfer coding
                piece_framed = f"{len(piece):x}\r\n".encode() + piece + b"\r\n"
                sock.sendall(piece_framed)
            else:
                sock.sendall(piece)
            sent[0] += len(piece)
    if attack.length is None:
        sock.sendall(b"0\r\n\r\n")


def read_answer(sock: socket.socket) -> bytes:
    data = b""
    try:
        while chunk := sock.recv(65536):
            data += chunk
    except (ConnectionResetError, TimeoutError):
        pass
    return data


# ---------------------------------------------------------------------- measuring


class Watch:
    """While an attack runs: the server's peak RSS, its children's, the bytes in its spool
    directories (every 10 ms) and the slowest health answer (every 20 ms)."""

    def __init__(self, server: psutil.Process, base: str, spools: list[Path]) -> None:
        self.server = server
        self.base = base
        self.spools = spools
        self.rss = 0
        self.children = 0
        self.spooled = 0
        self.left = 0
        self.lag = 0.0  # ms: the slowest health answer
        self.loop_max = 0.0  # ms: the server's own loop lag figure (loop_watch.py)
        self._halt = threading.Event()
        self._threads = [
            threading.Thread(target=self._sample),
            threading.Thread(target=self._probe),
        ]

    def __enter__(self) -> Watch:
        for thread in self._threads:
            thread.start()
        return self

    def __exit__(self, *_: object) -> None:
        time.sleep(0.3)  # what follows an answer (a worker's exit) counts too
        self._halt.set()
        for thread in self._threads:
            thread.join()
        self.left = spooled(self.server.pid, self.spools)  # still on disk after the answer

    def _sample(self) -> None:
        while not self._halt.is_set():
            try:
                self.rss = max(self.rss, self.server.memory_info().rss)
                kids = sum(c.memory_info().rss for c in self.server.children(recursive=True))
                self.children = max(self.children, kids)
            except psutil.Error:
                pass
            self.spooled = max(self.spooled, spooled(self.server.pid, self.spools))
            time.sleep(0.01)

    def _probe(self) -> None:
        with httpx.Client(base_url=self.base, timeout=30) as client:
            while not self._halt.is_set():
                start = time.perf_counter()
                answer = client.get("/api/health")
                self.lag = max(self.lag, (time.perf_counter() - start) * 1000)
                self.loop_max = max(self.loop_max, float(answer.json()["loop"]["max_ms"]))
                time.sleep(0.02)


def spooled(pid: int, spools: list[Path]) -> int:
    """Bytes on disk under `spools`: named files, and the server's open temporary files (a
    spooled upload has no name: it is unlinked when made)."""
    seen: set[int] = set()
    total = 0
    paths = [
        Path(root, name) for spool in spools for root, _, names in os.walk(spool) for name in names
    ]
    fds = Path(f"/proc/{pid}/fd")
    with contextlib.suppress(OSError):
        for fd in fds.iterdir():
            with contextlib.suppress(OSError):
                if any(os.readlink(fd).startswith(str(spool)) for spool in spools):
                    paths.append(fd)
    for path in paths:
        with contextlib.suppress(OSError):  # a file may go meanwhile
            info = os.stat(path)
            if info.st_ino not in seen:
                seen.add(info.st_ino)
                total += info.st_blocks * 512
    return total


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


def start_server(port: int, home: Path, log: Path | None) -> subprocess.Popen[bytes]:
    for name in ("data", "tmp"):
        (home / name).mkdir()
    env = {
        **os.environ,
        "SERVODESK_DATA_DIR": str(home / "data"),
        "TMPDIR": str(home / "tmp"),  # where Starlette spools uploads
    }
    command = [str(BIN / "servodesk"), "serve", "--sim", "--port", str(port)]
    out = log.open("wb") if log else subprocess.DEVNULL
    process = subprocess.Popen(command, env=env, stdout=out, stderr=out)
    deadline = time.monotonic() + 60
    while True:
        try:
            if len(httpx.get(f"http://127.0.0.1:{port}/api/nodes", timeout=1).json()) == 3:
                return process
        except (httpx.HTTPError, ValueError):
            pass
        if time.monotonic() > deadline or process.poll() is not None:
            process.kill()
            raise SystemExit("the server did not start")
        time.sleep(0.2)


def settle(base: str) -> float:
    """Wait (up to a minute) until the server's loop lag window holds nothing slow from
    before, so the figure read during an attack is the attack's; the window's max then."""
    deadline = time.monotonic() + 65
    while True:
        lag = float(httpx.get(f"{base}/api/health", timeout=30).json()["loop"]["max_ms"])
        if lag < LAG_TARGET_MS / 2 or time.monotonic() > deadline:
            return lag
        time.sleep(1.0)


def verdict(ok: bool) -> str:
    return "ok" if ok else "MISS"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bomb-mb", type=int, default=200, help="each container expands to")
    parser.add_argument("--bomb-containers", type=int, default=4)
    parser.add_argument("--json-mb", type=int, default=100)
    parser.add_argument("--pdos-mb", type=int, default=33)
    parser.add_argument("--upload-mb", type=int, default=300)
    parser.add_argument("--server-log", type=Path, help="the server's log (stalls) goes here")
    args = parser.parse_args()
    plan = attacks(args)
    home = Path(tempfile.mkdtemp(prefix="servodesk-hostile-"))
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    process = start_server(port, home, args.server_log)
    misses = 0
    try:
        server = psutil.Process(process.pid)
        time.sleep(2.0)  # start-up settles before the baseline
        idle = server.memory_info().rss
        print(
            f"idle server RSS {idle / MB:.0f} MB; target peak ≤ {RSS_TARGET:g}× = "
            f"{RSS_TARGET * idle / MB:.0f} MB; loop lag target ≤ {LAG_TARGET_MS:g} ms"
        )
        for attack in plan:
            settle(base)
            with Watch(server, base, [home / "tmp", home / "data" / "uploads"]) as watch:
                status, message, sent = send(port, attack)
            rss_ratio = watch.rss / idle / RSS_TARGET
            lag_ratio = watch.loop_max / LAG_TARGET_MS
            ok = rss_ratio <= 1 and lag_ratio <= 1 and status in (200, 413, 422)
            misses += not ok
            print(f"\n{attack.name} → {attack.method} {attack.path}")
            print(f"  answer {status}: {message}")
            print(
                f"  body sent before the answer {sent / MB:.1f} MB; spooled to disk: peak "
                f"{watch.spooled / MB:.1f} MB, {watch.left / MB:.1f} MB left after"
            )
            print(
                f"  server RSS peak {watch.rss / MB:.0f} MB = {watch.rss / idle:.2f}× idle "
                f"(ratio to target {rss_ratio:.2f}) {verdict(rss_ratio <= 1)}; "
                f"child processes peak {watch.children / MB:.0f} MB"
            )
            print(
                f"  event loop lag max {watch.loop_max:.0f} ms (ratio to target {lag_ratio:.2f}) "
                f"{verdict(lag_ratio <= 1)}; slowest health answer {watch.lag:.0f} ms"
            )
    finally:
        process.terminate()
        try:
            process.wait(timeout=20)
        except subprocess.TimeoutExpired:
            process.kill()
        shutil.rmtree(home, ignore_errors=True)
    print("\nall targets met" if not misses else f"\n{misses} attack(s) missed a target")
    return 1 if misses else 0


if __name__ == "__main__":
    raise SystemExit(main())
