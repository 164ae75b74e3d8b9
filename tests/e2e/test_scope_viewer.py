"""The scope viewer in Chromium, offline: the app's own rerun viewer opened from
/api/scope/viewer, a sine logged into the app's rerun server with the SDK, plotted through the
app's gRPC-web proxy, while every request to a host other than 127.0.0.1 is aborted and
recorded. The screenshot goes to /tmp/shots/scope_viewer.png."""

from __future__ import annotations

import io
import re
from collections.abc import Iterator
from pathlib import Path
from urllib.parse import urlsplit

import numpy as np
import pytest
import rerun as rr
from PIL import Image, ImageStat
from playwright.sync_api import Browser, ConsoleMessage, Route

from tests.live_server import serve_simulated

SHOTS = Path("/tmp/shots")
GRPC_SERVICE = "/rerun.sdk_comms.v1alpha1.MessageProxyService/"
RECORDING_ID = "scope-viewer-e2e"
# The viewer's state (protobuf bytes) names the active recording once its data came in.
SHOWS_RECORDING = f"""() => window._handle !== undefined &&
    new TextDecoder().decode(window._handle.viewer_state()).includes("{RECORDING_ID}")"""
PLOT_AREA = (260, 80, 900, 500)  # inside the time-series view at 1280×720, away from panels


@pytest.fixture
def app_server(tmp_path: Path) -> Iterator[tuple[str, Path]]:
    with serve_simulated(tmp_path, static_dir=None) as url:
        yield url, tmp_path


def rerun_grpc_url(data_dir: Path) -> str:
    """The app's rerun server as the SDK reaches it (its command line heads its log)."""
    command = (data_dir / "rerun" / "rerun-server.log").read_text().splitlines()[0]
    found = re.search(r"--port (\d+)", command)
    assert found, command
    return f"rerun+http://127.0.0.1:{found.group(1)}/proxy"


def log_sine(grpc_url: str) -> None:
    rec = rr.RecordingStream("servodesk-scope-e2e", recording_id=RECORDING_ID)
    rec.set_sinks(rr.GrpcSink(grpc_url))
    t = np.arange(0.0, 2.0, 0.002)
    rec.send_columns(
        "drives/1/position",
        indexes=[rr.TimeColumn("time", duration=t)],
        columns=rr.Scalars.columns(scalars=np.sin(2 * np.pi * t)),
    )
    rec.flush(timeout_sec=10)
    rec.disconnect()  # flushed: nothing left to send when the app stops


def test_the_viewer_plots_a_recording_offline(
    browser: Browser, app_server: tuple[str, Path]
) -> None:
    base, data_dir = app_server
    context = browser.new_context(viewport={"width": 1280, "height": 720})
    outside: list[str] = []
    own: list[tuple[str, str]] = []
    console: list[str] = []

    def route(target: Route) -> None:
        request = target.request
        if urlsplit(request.url).hostname != "127.0.0.1":
            outside.append(f"{request.method} {request.url}")
            target.abort()
            return
        own.append((request.method, urlsplit(request.url).path))
        target.continue_()

    def on_console(message: ConsoleMessage) -> None:
        if message.type in ("error", "warning", "info"):
            console.append(message.text[:200])

    context.route("**/*", route)
    page = context.new_page()
    page.on("console", on_console)
    try:
        viewer = page.request.get(f"{base}/api/scope/viewer")
        assert viewer.ok, viewer.text()
        described = viewer.json()
        assert described["running"] is True
        assert described["grpc_url"] == f"rerun+http://{urlsplit(base).netloc}/proxy"
        log_sine(rerun_grpc_url(data_dir))

        page.goto(base + described["url"])
        page.wait_for_function(SHOWS_RECORDING, timeout=25_000, polling=250)
        page.wait_for_timeout(1_500)  # a few frames of the software rasteriser
        SHOTS.mkdir(parents=True, exist_ok=True)
        png = page.screenshot(path=str(SHOTS / "scope_viewer.png"))
    finally:
        context.close()  # ends the endless gRPC-web stream before the app stops

    assert outside == [], f"the viewer reached outside 127.0.0.1: {outside}"
    assert not [line for line in console if "Content Security Policy" in line], console
    # everything came through the app: the page, its files and the gRPC-web stream
    paths = {path for _, path in own}
    assert {"/rerun/", "/rerun/re_viewer.js", "/rerun/re_viewer_bg.wasm"} <= paths
    assert ("POST", GRPC_SERVICE + "ReadMessages") in own
    assert not [method for method, _ in own if method == "OPTIONS"]  # same origin: no preflight
    # the plot is drawn: the canvas is not blank, and the sine's coloured line crosses the view
    image = Image.open(io.BytesIO(png)).convert("RGB")
    assert ImageStat.Stat(image.convert("L")).stddev[0] > 10
    saturation = np.asarray(image.crop(PLOT_AREA).convert("HSV"))[..., 1]
    assert int((saturation > 100).sum()) > 300  # no data: 0 (grey text only); the sine: ~1000
