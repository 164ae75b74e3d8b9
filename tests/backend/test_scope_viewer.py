"""The scope's rerun viewer: its server listens on loopback only and never phones home, it
starts once for concurrent callers and again after it died, says why when it cannot start;
the viewer page served through the app loads nothing from outside; live recordings reach a
gRPC-web client through the app's proxy as they are logged; the security middlewares stay in
front of it all."""

from __future__ import annotations

import asyncio
import json
import re
import socket
from collections.abc import Iterator
from pathlib import Path

import httpx
import numpy as np
import psutil  # type: ignore[import-untyped]  # no stubs installed; dev dependency
import pytest
import rerun as rr
from fastapi.testclient import TestClient

from servodesk.api.rerun_proxy import GRPC_SERVICE
from servodesk.app import create_app
from servodesk.errors import ScopeViewerError
from servodesk.scope.viewer_server import HOME_NAME, RerunServer
from servodesk.settings import Settings
from tests.live_server import serve_simulated

READ_MESSAGES = f"/{GRPC_SERVICE}/ReadMessages"
EMPTY_REQUEST = b"\x00\x00\x00\x00\x00"  # one gRPC-web frame: ReadMessagesRequest {}
GRPC_WEB = {
    "content-type": "application/grpc-web+proto",
    "accept": "application/grpc-web+proto",
    "x-grpc-web": "1",
}
# What makes a browser load something: src=, <link href=, CSS url()/@import, fetch(…)
LOADED = re.compile(
    r"""(?:\bsrc\s*=\s*["']?|<link\b[^>]*\bhref\s*=\s*["']?|url\(\s*["']?|@import\s+["']?"""
    r"""|fetch\(\s*["'])(?:https?:)?//""",
    re.I,
)


def outside_addresses() -> list[str]:
    """This machine's IPv4 addresses other than loopback."""
    return [
        address.address
        for addresses in psutil.net_if_addrs().values()
        for address in addresses
        if address.family == socket.AF_INET and not address.address.startswith("127.")
    ]


def connects(host: str, port: int) -> bool:
    try:
        with socket.create_connection((host, port), timeout=5):
            return True
    except ConnectionRefusedError:
        return False


def listening(port: int) -> list[tuple[str, int | None]]:
    """(address, pid) of every socket listening on `port`."""
    return [
        (conn.laddr.ip, conn.pid)
        for conn in psutil.net_connections(kind="inet")
        if conn.status == psutil.CONN_LISTEN and conn.laddr.port == port
    ]


@pytest.mark.anyio
async def test_the_rerun_server_listens_on_loopback_only_and_keeps_analytics_off(
    tmp_path: Path,
) -> None:
    server = RerunServer(tmp_path)
    assert not server.running
    await server.ensure_started()
    try:
        ports = (server.grpc_port, server.web_port)
        assert server.grpc_url == f"rerun+http://127.0.0.1:{server.grpc_port}/proxy"
        assert server.version == rr.__version__
        for port in ports:
            assert connects("127.0.0.1", port)
            assert {address for address, _ in listening(port)} == {"127.0.0.1"}
            for address in outside_addresses():  # none on a machine without a network
                assert not connects(address, port), f"rerun answers on {address}:{port}"
        # the wasm served once: rerun would record that (ServeWasm) if analytics were on
        async with httpx.AsyncClient(trust_env=False) as client:
            wasm = await client.get(f"{server.web_base}/re_viewer_bg.wasm")
            assert wasm.status_code == 200
        home = tmp_path / HOME_NAME
        config = json.loads((home / "config" / "rerun" / "analytics.json").read_text())
        assert config["analytics_enabled"] is False
        assert not (home / "data" / "rerun" / "analytics").exists()  # no pending events
        assert "analytics" not in (tmp_path / "rerun-server.log").read_text().lower()
    finally:
        await server.close()
    assert not server.running
    assert not any(connects("127.0.0.1", port) for port in ports)


@pytest.mark.anyio
async def test_concurrent_starts_share_one_process_which_restarts_after_it_died(
    tmp_path: Path,
) -> None:
    server = RerunServer(tmp_path)
    try:
        await asyncio.gather(*(server.ensure_started() for _ in range(5)))
        owners = {pid for _, pid in listening(server.grpc_port)}
        assert len(owners) == 1
        first = psutil.Process(owners.pop())
        assert first.cmdline()[1:3] == ["--serve-web", "--bind"]
        first.kill()
        first.wait(10)
        assert not server.running
        await server.ensure_started()
        assert server.running
        assert connects("127.0.0.1", server.grpc_port)
        assert (tmp_path / "rerun-server.log.1").is_file()  # the dead one's log is kept
    finally:
        await server.close()


@pytest.mark.anyio
async def test_a_viewer_that_cannot_start_says_why(tmp_path: Path) -> None:
    server = RerunServer(tmp_path, memory_limit="plenty")
    with pytest.raises(ScopeViewerError) as failed:
        await server.ensure_started()
    message = str(failed.value)
    assert "rerun-server.log" in message  # where to look
    assert "plenty" in message  # rerun's own complaint about the limit
    assert "\n" not in message
    assert not server.running
    await server.close()


@pytest.fixture
def client(tmp_path: Path) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path)
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


def test_the_viewer_page_through_the_app_loads_nothing_from_outside(client: TestClient) -> None:
    described = client.get("/api/scope/viewer")
    assert described.status_code == 200, described.text
    viewer = described.json()
    assert viewer["url"] == "/rerun/?url=rerun%2Bhttp%3A%2F%2Ftestserver%2Fproxy"
    assert viewer["grpc_url"] == "rerun+http://testserver/proxy"
    assert viewer["running"] is True
    assert viewer["version"] == rr.__version__

    page = client.get(viewer["url"])
    assert page.status_code == 200
    html = page.text
    assert LOADED.findall(html) == []
    for outside in ("fonts.googleapis", "fonts.gstatic", "rerun.io/script.js", "app.rerun.io"):
        assert outside not in html
    assert "check_for_updates_on_startup: false" in html  # no GitHub release check
    assert "hide_welcome_screen: true" in html  # no examples manifest from app.rerun.io
    assert "the viewer works offline" in html  # cross-origin fetch refused in the page
    policy = page.headers["content-security-policy"]
    assert "default-src 'self'" in policy
    assert "connect-src 'self'" in policy

    script = client.get("/rerun/re_viewer.js")
    assert script.status_code == 200
    assert script.headers["content-type"] == "text/javascript"
    revalidated = client.get(
        "/rerun/re_viewer.js", headers={"if-none-match": script.headers["etag"]}
    )
    assert revalidated.status_code == 304
    assert client.get("/rerun/no-such-file.js").status_code == 404
    assert client.get("/rerun", follow_redirects=False).headers["location"] == "/rerun/"


def test_a_viewer_that_cannot_start_is_a_503_in_one_line(
    client: TestClient, tmp_path: Path
) -> None:
    services = client.app.state.services  # type: ignore[attr-defined]
    services.viewer = RerunServer(tmp_path / "broken", memory_limit="plenty")
    for path in ("/api/scope/viewer", "/rerun/"):
        answer = client.get(path)
        assert answer.status_code == 503
        body = answer.json()
        assert body["error"] == "scope_viewer_unavailable"
        assert "did not start" in body["message"] or "exited" in body["message"]
        assert "\n" not in body["message"]


def test_the_security_guards_stay_in_front_of_the_proxy(client: TestClient) -> None:
    headers = {**GRPC_WEB, "origin": "http://evil.example"}
    refused = client.post(READ_MESSAGES, content=EMPTY_REQUEST, headers=headers)
    assert refused.status_code == 403
    assert refused.json()["error"] == "cross_origin"
    rebound = client.get("/rerun/", headers={"host": "evil.example"})
    assert rebound.status_code == 400
    assert client.post(READ_MESSAGES, content=b"{}").status_code == 415
    assert client.options(READ_MESSAGES).status_code == 405  # same origin: no CORS to answer


def test_live_recordings_stream_through_the_apps_grpc_web_proxy(tmp_path: Path) -> None:
    recording_id = "through-the-proxy"
    with (
        serve_simulated(tmp_path, static_dir=None) as base,
        httpx.Client(base_url=base, timeout=10, trust_env=False) as http,
    ):
        assert http.get("/api/scope/viewer").status_code == 200
        command = (tmp_path / "rerun" / "rerun-server.log").read_text().splitlines()[0]
        port = re.search(r"--port (\d+)", command)
        assert port, command
        headers = {**GRPC_WEB, "origin": base}  # as the viewer page sends it: same origin
        with http.stream("POST", READ_MESSAGES, content=EMPTY_REQUEST, headers=headers) as stream:
            assert stream.status_code == 200
            assert stream.headers["content-type"] == "application/grpc-web+proto"
            # logged after the stream opened: it arrives while the stream stays open
            rec = rr.RecordingStream("servodesk-scope-test", recording_id=recording_id)
            rec.set_sinks(rr.GrpcSink(f"rerun+http://127.0.0.1:{port.group(1)}/proxy"))
            t = np.arange(0.0, 1.0, 0.01)
            rec.send_columns(
                "drives/1/position",
                indexes=[rr.TimeColumn("time", duration=t)],
                columns=rr.Scalars.columns(scalars=np.sin(t)),
            )
            rec.flush(timeout_sec=10)
            received = b""
            for chunk in stream.iter_raw():
                received += chunk
                if recording_id.encode() in received:
                    break
            assert received[:1] == b"\x00"  # a gRPC-web data frame
            rec.disconnect()
