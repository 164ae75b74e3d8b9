"""The Scope page in Chromium against the simulated drives, in two walks that share the app and
the browser. The capture: pick node 1's position and velocity, pause the live view from its
button, jog node 1 in PV (through the API, keep-alives from a thread), start a capture from the
page, follow it (state, samples, live readouts), stop it and export it as CSV from the captures
list. The viewer: with the live view shown, a short capture of the same jog plotted live by the
embedded rerun viewer, then re-opened in it from its .rrd. Screenshots go to
/tmp/shots/scope_*.png."""

from __future__ import annotations

import csv
import io
import re
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import httpx
import numpy as np
import pytest
from PIL import Image, ImageStat
from playwright.sync_api import Browser, BrowserContext, Frame, Locator, Page, Request, expect

from servodesk.app import STATIC_DIR
from tests.live_server import serve_simulated

SHOTS = Path("/tmp/shots")
CLIENT = {"X-Client-Id": "scope-e2e"}
JOG_RPM = 120
POSITION, VELOCITY = "6064h:00", "606Ch:00"


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """The app as conftest serves it, but with the drives' heartbeat consumer (1016h) at 3 s
    instead of 300 ms. The viewer draws with Chromium's software rasteriser, which on a small,
    busy machine can starve the app's own heartbeat for more than 300 ms during a capture: the
    drive then trips its CAN-state alarm (MDi alarm 61, 003Dh) and the jog stops. This test is
    about the Scope page, not about that safety timing (tests/backend cover it)."""
    if not (STATIC_DIR / "index.html").is_file():
        pytest.fail("the frontend is not built: run `make frontend` (make test does it)")
    with pytest.MonkeyPatch.context() as env:
        env.setenv("SERVODESK_HEARTBEAT_CONSUMER_MS", "3000")
        with serve_simulated(tmp_path_factory.mktemp("scope")) as url:
            yield url


def shows_recording(recording_id: str) -> str:
    """The viewer's state (protobuf bytes) names a recording once its data came in."""
    return f"""() => window._handle !== undefined &&
        new TextDecoder().decode(window._handle.viewer_state()).includes("{recording_id}")"""


def ok(response: httpx.Response) -> Any:
    assert response.is_success, f"{response.request.url}: {response.status_code} {response.text}"
    return response.json()


@contextmanager
def jogging(server: str, node: int, rpm: float) -> Iterator[list[str]]:
    """A PV jog held as the browser holds it: keep-alives every 150 ms from a thread. On a busy
    machine a keep-alive can miss the 500 ms window and the server stops the axis (as it must):
    the thread then holds the button again (a new jog, after a fault reset if the drive
    faulted), as the user would. Yields the stops it saw."""
    stops: list[str] = []
    with httpx.Client(base_url=server, timeout=10) as api:
        # the simulated limit switches out of the way of the jog
        for index, rev in ((0x5FF1, -1000), (0x5FF2, 1000)):
            ok(api.put(f"/api/nodes/{node}/sdo/{index:04X}/0", json={"value": rev * 131072}))

        def hold(client: httpx.Client) -> str:
            if client.get(f"/api/nodes/{node}/drive").json()["state"] == "fault":
                ok(client.post(f"/api/nodes/{node}/drive/fault-reset", headers=CLIENT))
            ok(client.post(f"/api/nodes/{node}/drive/enable", headers=CLIENT))
            body = {"mode": "pv", "velocity_rpm": rpm, "keepalive_ms": 500}
            jog = ok(client.post(f"/api/nodes/{node}/jog", headers=CLIENT, json=body))
            return str(jog["jog_id"])

        held = [hold(api)]
        done = threading.Event()

        def keep_alive() -> None:
            with httpx.Client(base_url=server, timeout=5) as beat:
                while not done.wait(0.15):
                    try:
                        answer = beat.post(f"/api/jog/{held[-1]}/keepalive")
                        if answer.status_code == 200:
                            continue
                        stops.append(answer.json().get("message", answer.text))
                        held.append(hold(beat))
                    except (httpx.HTTPError, AssertionError) as error:
                        stops.append(f"{type(error).__name__}: {error}")

        thread = threading.Thread(target=keep_alive, name="jog-keepalive", daemon=True)
        thread.start()
        try:
            yield stops
        finally:
            done.set()
            thread.join()
            api.delete(f"/api/jog/{held[-1]}")


def drive_report(server: str, node: int) -> str:
    """The drive's state and the active faults, for a failure's message."""
    drive = httpx.get(f"{server}/api/nodes/{node}/drive", timeout=10).json()
    faults = httpx.get(f"{server}/api/faults/active", timeout=10).json()
    return f"node {node} {drive['state']} at {drive.get('velocity_rpm')} rpm; faults: {faults}"


def viewer_frame(page: Page) -> Frame:
    handle = page.get_by_test_id("rerun-viewer").element_handle()
    assert handle is not None
    frame = handle.content_frame()
    assert frame is not None
    return frame


def shot(page: Page, name: str, selector: str | None = None) -> bytes:
    """A screenshot of the page, or of one element by its box (the viewer repaints all the
    time, so waiting for it to be "stable" as an element screenshot does may never end)."""
    SHOTS.mkdir(parents=True, exist_ok=True)
    path = str(SHOTS / name)
    if selector is None:
        return page.screenshot(path=path)
    element = page.locator(selector).first
    element.scroll_into_view_if_needed()
    box = element.bounding_box()
    assert box is not None, selector
    return page.screenshot(path=path, clip=box)


def assert_plotted(png: bytes) -> None:
    """Not blank: contrast, and the series' coloured lines run across the plots (the legends'
    coloured dots cover a few columns only; the grey UI none)."""
    image = Image.open(io.BytesIO(png)).convert("RGB")
    assert ImageStat.Stat(image.convert("L")).stddev[0] > 10
    width, height = image.size
    plots = image.crop((int(width * 0.02), int(height * 0.08), int(width * 0.7), int(height * 0.7)))
    saturated = np.asarray(plots.convert("HSV"))[..., 1] > 100
    columns = int(saturated.any(axis=0).sum())
    assert columns > 0.6 * plots.width, f"no plotted line across the viewer ({columns} columns)"


def new_page(browser: Browser) -> tuple[BrowserContext, Page]:
    # a modest window: the viewer draws with a software rasteriser on few cores
    context = browser.new_context(viewport={"width": 1280, "height": 800}, accept_downloads=True)
    page = context.new_page()
    page.set_default_timeout(30_000)
    return context, page


def choose_signals(page: Page, duration_s: int, name: str) -> Locator:
    """Node 1's position and velocity, the duration and the name; the check runs by itself:
    both signals in a TPDO, the bus load, Start enabled. Returns the Start button."""
    page.get_by_role("button", name="Position 6064h").click()
    page.get_by_role("button", name="Velocity 606Ch").click()
    chosen = page.get_by_role("list", name="Chosen signals")
    expect(chosen.get_by_role("listitem")).to_have_count(2)
    page.get_by_label("Duration").fill(str(duration_s))
    page.get_by_label("Name").fill(name)
    sources = page.get_by_role("table", name="Signal sources")
    expect(sources.get_by_role("row", name=re.compile("6064h:00"))).to_contain_text("TPDO")
    expect(sources.get_by_role("row", name=re.compile("606Ch:00"))).to_contain_text("TPDO")
    expect(page.get_by_role("meter", name="Bus load during the capture")).to_be_visible()
    start = page.get_by_role("button", name="● Start capture")
    expect(start).to_be_enabled(timeout=30_000)  # the viewer's rendering slows the page
    return start


def named_capture(server: str, name: str) -> dict[str, Any] | None:
    captures = ok(httpx.get(f"{server}/api/scope/captures", timeout=5))
    return next((c for c in captures if c["name"] == name), None)


def wait_until_ended(server: str, name: str, timeout_s: float) -> dict[str, Any]:
    """The capture named `name` from the server once it ended (done or failed): the page may be
    slow to say so while the viewer's software rendering holds its main thread."""
    deadline = time.monotonic() + timeout_s
    capture = named_capture(server, name)
    while (capture is None or capture["state"] not in ("done", "failed")) and (
        time.monotonic() < deadline
    ):
        time.sleep(0.25)
        capture = named_capture(server, name)
    assert capture is not None, f"no capture {name!r} on the server"
    assert capture["state"] in ("done", "failed"), f"not ended after {timeout_s:.0f} s: {capture}"
    return capture


def test_capture_a_jog_with_the_live_view_paused_and_export_csv(
    browser: Browser, server: str
) -> None:
    context, page = new_page(browser)
    try:
        capture_with_the_live_view_paused(page, server)
    finally:
        context.close()


class InFlight:
    """The page's requests not answered yet (the frames included): what a wait that ran out
    was waiting behind, should it run out."""

    def __init__(self, page: Page) -> None:
        self.open: dict[Request, float] = {}
        page.on("request", self._sent)
        page.on("requestfinished", self._ended)
        page.on("requestfailed", self._ended)

    def _sent(self, request: Request) -> None:
        self.open[request] = time.monotonic()

    def _ended(self, request: Request) -> None:
        self.open.pop(request, None)

    def __str__(self) -> str:
        now = time.monotonic()
        waiting = [f"{r.method} {r.url} ({now - t:.0f} s)" for r, t in self.open.items()]
        return f"{len(waiting)} requests unanswered: " + "; ".join(waiting)


def capture_with_the_live_view_paused(page: Page, server: str) -> None:
    in_flight = InFlight(page)
    # a user who paused the live view before (the page remembers it; the switch itself is in
    # ScopePage.test.tsx): the viewer never starts, so its start-up cannot hold the page
    page.add_init_script("localStorage.setItem('servodesk.scope.liveView', 'paused')")
    page.goto(f"{server}/scope")
    expect(page.get_by_role("heading", name="Scope", level=1)).to_be_visible()
    expect(page.get_by_role("button", name="Show live view")).to_be_visible()
    expect(page.get_by_test_id("rerun-viewer")).to_have_count(0)
    paused = page.get_by_test_id("live-view-paused")
    expect(paused).to_contain_text("captures still record")
    expect(page.get_by_role("button", name="Show live view")).to_be_visible()
    start = choose_signals(page, 60, "e2e jog")  # stopped from the page long before
    shot(page, "scope_plan.png")

    with jogging(server, 1, JOG_RPM) as stops:
        start.click()
        # setting the bus up (SYNC, TPDOs, NMT) is quick
        try:
            expect(page.get_by_test_id("capture-state")).to_have_text("Recording", timeout=30_000)
        except AssertionError as error:  # the server's side of it: did the start arrive?
            captures = httpx.get(f"{server}/api/scope/captures", timeout=5).text
            why = f"the server's captures: {captures}\n{in_flight}"
            raise AssertionError(f"{error}\n{why}") from error
        expect(start).to_be_disabled()
        expect(page.get_by_test_id("rerun-viewer")).to_have_count(0)  # still paused
        readouts = page.get_by_role("table", name="Live readouts")
        velocity_row = readouts.get_by_role("row", name=re.compile("606Ch:00"))
        try:
            expect(velocity_row).to_contain_text(re.compile(r"1[12]\d(\.\d+)? rpm"), timeout=20_000)
        except AssertionError as error:
            report = f"{drive_report(server, 1)}; jog stops: {stops}"
            raise AssertionError(f"{error}\n{report}") from error
        page.wait_for_timeout(2_000)  # the sparklines fill
        shot(page, "scope_recording.png", ".scope-capture")
        page.locator(".scope-capture").get_by_role("button", name="■ Stop").click()
        expect(page.get_by_test_id("capture-state")).to_have_text("Done", timeout=45_000)
    # the plan is checked again once the capture ended
    expect(start).to_be_enabled(timeout=30_000)
    samples = int(page.get_by_test_id("capture-samples").inner_text().replace(",", ""))
    assert samples > 1000
    capture = named_capture(server, "e2e jog")
    assert capture is not None
    assert capture["state"] == "done"
    assert "stopped by the user" in capture["notes"]

    # export CSV from the list: both signals' rows, the velocity at the jog's speed
    row = page.locator(f"tr[data-capture='{capture['id']}']")
    expect(row).to_contain_text("done")
    with page.expect_download() as download:
        row.get_by_role("link", name=f"Export capture {capture['id']} as CSV").click()
    text = Path(download.value.path()).read_text()
    rows = list(csv.DictReader(io.StringIO(text)))
    objects = {r["object"] for r in rows}
    assert {POSITION, VELOCITY} <= objects, objects
    speeds = np.array([float(r["value"]) for r in rows if r["object"] == VELOCITY])
    assert len(speeds) > 500
    at_speed = float(np.mean(np.abs(speeds - JOG_RPM) < 5))
    assert at_speed > 0.3, f"{at_speed:.0%} of the samples at {JOG_RPM} rpm; stops: {stops}"
    positions = [float(r["value"]) for r in rows if r["object"] == POSITION]
    assert max(positions) - min(positions) > 1.0  # rev: the axis turned
    shot(page, "scope_list.png", ".scope-list")
    # the page as it is with the live view paused: the note, the captures below it
    expect(paused).to_be_visible()
    paused.scroll_into_view_if_needed()
    shot(page, "scope_page.png")


# the viewer's walk-through (live, then the .rrd re-opened) waits on the viewer's software
# rendering three times, each bounded on its own below; on 2 busy cores the sum can pass the
# suite's 120 s default
@pytest.mark.timeout(240)
def test_the_viewer_plots_a_capture_live_and_from_its_rrd(browser: Browser, server: str) -> None:
    context, page = new_page(browser)
    try:
        view_a_capture(page, server)
    finally:
        context.close()  # ends the viewer's endless gRPC-web stream before the app stops


def view_a_capture(page: Page, server: str) -> None:
    page.goto(f"{server}/scope")
    expect(page.get_by_role("heading", name="Scope", level=1)).to_be_visible()
    expect(page.get_by_text("Live: every capture as it records")).to_be_visible()
    # the viewer compiles ~40 MB of wasm: let it start before the drive moves
    viewer_frame(page).wait_for_function("() => window._handle !== undefined", timeout=60_000)
    start = choose_signals(page, 3, "e2e viewer")

    with jogging(server, 1, JOG_RPM) as stops:
        start.click()
        # the server's word on its end: the page may lag while the viewer draws the capture
        try:
            capture = wait_until_ended(server, "e2e viewer", 45)
        except AssertionError as error:
            report = f"{drive_report(server, 1)}; jog stops: {stops}"
            raise AssertionError(f"{error}\n{report}") from error
    assert capture["state"] == "done", capture

    # the embedded viewer got the capture live (WebGL on SwiftShader: give it time)
    viewer_frame(page).wait_for_function(
        shows_recording(capture["recording_id"]), timeout=60_000, polling=250
    )
    page.wait_for_timeout(2_500)  # a few frames of the software rasteriser
    assert_plotted(shot(page, "scope_viewer_live.png", "[data-testid=rerun-viewer]"))

    # re-open it in the viewer from its .rrd
    row = page.locator(f"tr[data-capture='{capture['id']}']")
    expect(row).to_contain_text("done")
    row.get_by_role("button", name=f"Open capture {capture['id']} in the viewer").click()
    opened = f"Capture {capture['id']} · e2e viewer from its recording"
    expect(page.get_by_text(opened)).to_be_visible()
    viewer_frame(page).wait_for_function(
        shows_recording(capture["recording_id"]), timeout=60_000, polling=250
    )
    page.wait_for_timeout(2_500)
    assert_plotted(shot(page, "scope_viewer_rrd.png", "[data-testid=rerun-viewer]"))
    page.get_by_role("button", name="Back to the live view").click()
    expect(page.get_by_text("Live: every capture as it records")).to_be_visible()
    viewer_frame(page).wait_for_function("() => window._handle !== undefined", timeout=60_000)
