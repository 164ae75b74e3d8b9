"""The app's own rerun server: rerun's web viewer and its gRPC message proxy, run as the rerun
CLI bundled with the installed rerun-sdk (viewer, server and SDK are one version by
construction), bound to loopback and reached through the app's origin (api/rerun_proxy.py).

The SDK's in-process `rr.serve_grpc` binds every interface and has no bind option, so the CLI
runs as a child process with `--bind 127.0.0.1`. It starts on first use, restarts when it died,
and is stopped with the app. It never phones home: it gets a private config directory whose
analytics.json says disabled (rerun reads it through XDG_CONFIG_HOME; there is no env switch
that turns analytics off).
"""

from __future__ import annotations

import asyncio
import contextlib
import importlib.util
import json
import logging
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path
from typing import IO

import httpx
import rerun

from servodesk.errors import ScopeViewerError

log = logging.getLogger(__name__)

LOOPBACK = "127.0.0.1"
START_TIMEOUT_S = 15.0
STOP_TIMEOUT_S = 5.0
LOG_NAME = "rerun-server.log"
HOME_NAME = "rerun-home"  # the child's private XDG config/data: analytics off, nothing shared
# rerun would take these from the user's environment: forced analytics, another rerun binary
_DROPPED_ENV = ("FORCE_RERUN_ANALYTICS", "RERUN_CLI_PATH")


def rerun_command() -> tuple[list[str], bool]:
    """The rerun CLI of the installed rerun-sdk and whether it is a Python launcher.

    The `rerun` next to sys.executable (and `python -m rerun`) is a Python script that runs
    rerun_cli/rerun as *its* child: signalling it would orphan the real server, so the binary
    itself comes first; the launchers are the fallback, run in their own process group."""
    spec = importlib.util.find_spec("rerun_cli")
    name = "rerun.exe" if sys.platform == "win32" else "rerun"
    for location in (spec.submodule_search_locations or []) if spec else []:
        binary = Path(location) / name
        if binary.is_file() and os.access(binary, os.X_OK):
            return [str(binary)], False
    script = Path(sys.executable).parent / name
    if script.is_file():
        return [str(script)], True
    return [sys.executable, "-m", "rerun"], True


def _free_port(taken: set[int]) -> int:
    while True:
        with socket.socket() as sock:
            sock.bind((LOOPBACK, 0))
            port: int = sock.getsockname()[1]
        if port not in taken:
            return port


async def _accepts(port: int) -> bool:
    try:
        _, writer = await asyncio.wait_for(asyncio.open_connection(LOOPBACK, port), 1.0)
    except (OSError, TimeoutError):
        return False
    writer.close()
    with contextlib.suppress(OSError):
        await writer.wait_closed()
    return True


def _private_environment(home: Path) -> dict[str, str]:
    """The child's environment: its own config dir with analytics disabled (written before each
    start, so the first-run banner never shows and nothing is ever sent), no colour codes."""
    config, data = home / "config", home / "data"
    analytics = config / "rerun" / "analytics.json"
    analytics.parent.mkdir(parents=True, exist_ok=True)
    settings = {
        "analytics_enabled": False,
        "analytics_id": "servodesk-offline",
        "metadata": {},
        "config_file_path": str(analytics),
        "data_dir_path": str(data / "rerun" / "analytics"),
    }
    analytics.write_text(json.dumps(settings), encoding="utf-8")
    env = {key: value for key, value in os.environ.items() if key not in _DROPPED_ENV}
    env.update(XDG_CONFIG_HOME=str(config), XDG_DATA_HOME=str(data), NO_COLOR="1")
    return env


class _ExitedEarly(ScopeViewerError):
    """rerun exited before it listened (a port taken meanwhile, a broken install)."""


class RerunServer:
    """rerun's web viewer and gRPC server as one loopback-only child process (lazily started)."""

    def __init__(self, log_dir: Path, *, memory_limit: str = "512MiB") -> None:
        self.log_dir = log_dir
        self.log_path = log_dir / LOG_NAME
        self.memory_limit = memory_limit
        self.version: str = rerun.__version__
        self._command, self._launcher = rerun_command()
        self._process: subprocess.Popen[bytes] | None = None
        self._log_file: IO[bytes] | None = None
        self._ports: tuple[int, int] | None = None  # (grpc, web) of the last start
        self._lock = asyncio.Lock()  # concurrent first requests start one process
        self._client: httpx.AsyncClient | None = None

    @property
    def running(self) -> bool:
        return self._process is not None and self._process.poll() is None

    @property
    def grpc_port(self) -> int:
        return self._started_ports()[0]

    @property
    def web_port(self) -> int:
        return self._started_ports()[1]

    @property
    def grpc_url(self) -> str:
        """What an SDK RecordingStream's GrpcSink connects to (the app's own scope)."""
        return f"rerun+http://{LOOPBACK}:{self.grpc_port}/proxy"

    @property
    def grpc_base(self) -> str:
        """The gRPC(-web) server as plain HTTP, for the proxy."""
        return f"http://{LOOPBACK}:{self.grpc_port}"

    @property
    def web_base(self) -> str:
        return f"http://{LOOPBACK}:{self.web_port}"

    @property
    def build_id(self) -> str:
        """Changes when the rerun binary does: the viewer files' ETag."""
        try:
            stat = Path(self._command[0]).stat()
        except OSError:
            return self.version
        return f"{self.version}-{stat.st_size:x}-{stat.st_mtime_ns:x}"

    @property
    def client(self) -> httpx.AsyncClient:
        """The proxy's connection pool to this server (never through an HTTP proxy)."""
        if self._client is None:  # ensure_started builds it off the loop
            self._client = _new_client()
        return self._client

    def _started_ports(self) -> tuple[int, int]:
        if self._ports is None:
            raise ScopeViewerError("the scope viewer has not been started")
        return self._ports

    async def ensure_started(self) -> None:
        if self._client is None:
            # httpx loads the CA bundle for its default TLS context: 100+ ms of the loop on a
            # busy host, were it built on first use by the proxy (a quick stop waits that long)
            self._client = await asyncio.to_thread(_new_client)
        async with self._lock:
            if self.running:
                return
            await self._stop()  # a process that died: reap it before the next
            for attempt in (1, 2):
                try:
                    await self._start()
                    return
                except _ExitedEarly:
                    # a port picked free can be taken before rerun binds it: again, new ports
                    await self._stop()
                    if attempt == 2:
                        raise
                except ScopeViewerError:
                    await self._stop()
                    raise

    async def close(self) -> None:
        async with self._lock:
            await self._stop()
        if self._client is not None:
            await self._client.aclose()
            self._client = None

    async def _start(self) -> None:
        self.log_dir.mkdir(parents=True, exist_ok=True)
        grpc_port = _free_port(set())
        web_port = _free_port({grpc_port})
        command = [
            *self._command,
            "--serve-web",
            "--bind",
            LOOPBACK,
            "--port",
            str(grpc_port),
            "--web-viewer-port",
            str(web_port),
            "--server-memory-limit",
            self.memory_limit,
        ]
        self._process = await asyncio.to_thread(self._spawn, command)
        self._ports = (grpc_port, web_port)
        deadline = time.monotonic() + START_TIMEOUT_S
        while not (await _accepts(grpc_port) and await _accepts(web_port)):
            if self._process.poll() is not None:
                raise _ExitedEarly(self._failure(f"exited with code {self._process.returncode}"))
            if time.monotonic() > deadline:
                raise ScopeViewerError(
                    self._failure(f"did not listen within {START_TIMEOUT_S:.0f} s")
                )
            await asyncio.sleep(0.05)
        log.info("rerun %s viewer on %s, gRPC on %s", self.version, web_port, grpc_port)

    def _spawn(self, command: list[str]) -> subprocess.Popen[bytes]:
        if self.log_path.exists():  # keep the previous run's log (why did it die?)
            self.log_path.replace(self.log_path.with_suffix(".log.1"))
        self._log_file = self.log_path.open("wb")
        self._log_file.write(f"servodesk: {' '.join(command)}\n".encode())
        self._log_file.flush()
        try:
            # Same process group as the app (the binary): Ctrl+C stops it too, which also ends
            # the viewers' endless gRPC streams that uvicorn would otherwise wait for.
            return subprocess.Popen(
                command,
                stdin=subprocess.DEVNULL,
                stdout=self._log_file,
                stderr=subprocess.STDOUT,
                env=_private_environment(self.log_dir / HOME_NAME),
                cwd=self.log_dir,
                start_new_session=self._launcher,
            )
        except OSError as error:
            raise ScopeViewerError(
                f"could not run rerun ({command[0]}): {error}; reinstall rerun-sdk"
            ) from error

    def _failure(self, what: str) -> str:
        return (
            f"the scope viewer (rerun {self.version}) {what}: {self._log_tail()} "
            f"— see {self.log_path}"
        )

    def _log_tail(self) -> str:
        try:
            with self.log_path.open("rb") as file:
                file.seek(max(0, file.seek(0, os.SEEK_END) - 4096))
                lines = file.read().decode("utf-8", "replace").splitlines()
        except OSError:
            return "no log"
        useful = [line.strip() for line in lines if line.strip() and "servodesk:" not in line]
        return useful[-1] if useful else "no output"

    async def _stop(self) -> None:
        process, self._process = self._process, None
        if process is not None:
            await asyncio.to_thread(self._terminate, process)
        if self._log_file is not None:
            self._log_file.close()
            self._log_file = None

    def _terminate(self, process: subprocess.Popen[bytes]) -> None:
        if process.poll() is not None:
            return
        self._signal(process, kill=False)
        try:
            process.wait(STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            log.warning("rerun did not stop within %.0f s: killing it", STOP_TIMEOUT_S)
            self._signal(process, kill=True)
            process.wait()

    def _signal(self, process: subprocess.Popen[bytes], *, kill: bool) -> None:
        """SIGTERM, or SIGKILL; on Windows (no signals, no process groups: the launcher is not
        used there) TerminateProcess either way."""
        with contextlib.suppress(ProcessLookupError):
            if self._launcher and sys.platform != "win32":
                # the launcher and the rerun binary it runs
                os.killpg(process.pid, signal.SIGKILL if kill else signal.SIGTERM)
            elif kill:
                process.kill()
            else:
                process.terminate()


def _new_client() -> httpx.AsyncClient:
    return httpx.AsyncClient(trust_env=False, timeout=httpx.Timeout(10.0))
