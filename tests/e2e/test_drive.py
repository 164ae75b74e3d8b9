"""The Drive tab in Chromium against the simulated drives: enable node 1 (the panel's own way
out of NMT Pre-operational), hold-to-run PV jog held for a second and released (the axis
stops), homing method 35; screenshots of the panel, the state diagram and homing diagrams."""

from __future__ import annotations

import json
import re
import time
import urllib.request

from playwright.sync_api import Page, expect

from tests.e2e.conftest import SCREENSHOTS


def shot(page: Page, selector: str, name: str) -> None:
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    element = page.locator(selector).first
    element.scroll_into_view_if_needed()
    element.screenshot(path=str(SCREENSHOTS / name))


def drive_state(server: str, node: int) -> dict[str, object]:
    with urllib.request.urlopen(f"{server}/api/nodes/{node}/drive", timeout=5) as answer:
        state: dict[str, object] = json.load(answer)
        return state


def jogs(server: str, node: int) -> list[str]:
    """The node's last audit entries (a jog start, and a stop with its reason and by whom)."""
    with urllib.request.urlopen(f"{server}/api/audit?node={node}", timeout=5) as answer:
        entries: list[dict[str, object]] = json.load(answer)
    return [f"{e['user']}: {e['what']} ({e['result']})" for e in entries[:6]]


def velocity(server: str, node: int) -> float:
    """606Ch read from the drive now (rpm on the three profiles): the Drive page's shared
    reading may hold a value read in turn up to a few readings ago."""
    return float(sdo_value(server, node, 0x606C))


def enable(page: Page) -> None:
    """Enable, starting the node first if the panel says NMT is why it will not."""
    page.get_by_role("button", name="Enable", exact=True).click()
    state = page.get_by_test_id("drive-state")
    why = page.get_by_role("alert", name="Why won't it enable?")
    expect(state.or_(why).first).to_be_visible()
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        if state.text_content() == "Operation enabled":
            return
        start = why.get_by_role("button", name=re.compile(r"^Start node"))
        if why.count() and start.count():
            start.click()
            break
        page.wait_for_timeout(100)
    expect(state).to_have_text("Operation enabled", timeout=10_000)


def test_enable_jog_pv_and_home_node_1(page: Page, server: str) -> None:
    page.goto(f"{server}/nodes/1/drive")
    diagram = page.get_by_test_id("state-diagram")
    expect(diagram).to_be_visible()
    expect(page.get_by_role("list", name="Statusword bits")).to_be_visible()
    expect(page.get_by_role("button", name="Quick stop node 1")).to_be_visible()

    enable(page)
    expect(diagram).to_have_attribute("aria-label", re.compile("Operation enabled"))
    expect(page.locator('[data-state="operation_enabled"]')).to_have_class(re.compile("current"))
    shot(page, "[data-testid=state-diagram]", "drive_state_diagram.png")

    # PV: hold the button for a second, let go: the axis stops
    page.get_by_role("tab", name="Profile velocity (PV)").click()
    page.get_by_label("Speed (rpm)").fill("120")
    button = page.get_by_role("button", name=re.compile(r"^Hold \+120 rpm"))
    box = button.bounding_box()
    assert box is not None
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.down()
    expect(page.get_by_test_id("jog-pv-status")).to_contain_text("Moving")
    page.wait_for_timeout(1000)
    moving = velocity(server, 1)
    status = page.get_by_test_id("jog-pv-status").text_content()
    page.mouse.up()
    assert moving > 50, (
        f"the axis should turn while held (velocity {moving} rpm); the page said {status!r}; "
        f"the server's jogs: {jogs(server, 1)}"
    )
    deadline = time.monotonic() + 5
    while abs(velocity(server, 1)) > 0.5 and time.monotonic() < deadline:
        time.sleep(0.1)
    assert abs(velocity(server, 1)) <= 0.5, "the axis should stop after release"
    expect(page.get_by_test_id("jog-pv-status")).to_contain_text("Stopped")

    # homing: every method drawn; 35 sets the current position as home
    homing = page.get_by_role("region", name="Homing")
    expect(homing.get_by_test_id("homing-diagram-17")).to_be_visible()
    shot(page, "[data-testid=homing-diagram-17]", "drive_homing_17.png")
    shot(page, "[data-testid=homing-diagram-23]", "drive_homing_23.png")
    shot(page, ".homing-methods", "drive_homing_methods.png")
    homing.get_by_role("radio", name=re.compile(r"^35\b")).check()
    homing.get_by_role("button", name="Start homing (method 35)").click()
    expect(homing.get_by_test_id("homing-progress")).to_contain_text(
        "Homing attained", timeout=10_000
    )
    homed = drive_state(server, 1)
    assert isinstance(homed["homing"], dict)
    assert homed["homing"]["phase"] == "attained"
    shot(page, ".drive-homing", "drive_homing_result.png")

    # the whole panel in one picture: a viewport tall enough that nothing scrolls
    page.set_viewport_size({"width": 1366, "height": 2400})
    shot(page, ".drive-page", "drive_panel.png")


def test_network_page_quick_stops(page: Page, server: str) -> None:
    page.goto(server)
    page.get_by_role("button", name="Scan", exact=True).click()
    expect(page.get_by_role("button", name="Quick stop node 1")).to_be_visible()
    page.get_by_role("button", name="■ Quick stop all").click()
    expect(page.get_by_role("status").filter(has_text="Stopped node")).to_be_visible()


def sdo_value(server: str, node: int, index: int, sub: int = 0) -> int:
    url = f"{server}/api/nodes/{node}/sdo/{index:04X}/{sub}"
    with urllib.request.urlopen(url, timeout=5) as answer:
        value: int = json.load(answer)["value"]
        return value


def test_jog_ramps_and_transition_buttons_node_3(page: Page, server: str) -> None:
    page.goto(f"{server}/nodes/3/drive")
    expect(page.get_by_test_id("state-diagram")).to_be_visible()
    enable(page)
    jog = page.get_by_role("region", name="Jog")

    # PV at a chosen acceleration: 300 rpm/s to 120 rpm takes 0.4 s
    jog.get_by_role("tab", name="Profile velocity (PV)").click()
    jog.get_by_label("Speed (rpm)").fill("120")
    jog.get_by_label("Acceleration (rpm/s)").fill("300")
    shot(page, ".drive-jog", "drive_jog_pv.png")
    button = jog.get_by_role("button", name=re.compile(r"^Hold \+120 rpm"))
    box = button.bounding_box()
    assert box is not None
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.down()
    expect(page.get_by_test_id("jog-pv-status")).to_contain_text("Moving")
    # 6083h/6084h as written: 300 rpm/s = 5 rev/s², 100 000 user units per rev, per ms
    assert sdo_value(server, 3, 0x6083) == sdo_value(server, 3, 0x6084) == 500
    page.wait_for_timeout(1000)
    moving = velocity(server, 3)
    page.mouse.up()
    assert 100 < moving <= 121, f"at speed after the ramp (velocity {moving} rpm)"
    expect(page.get_by_test_id("jog-pv-status")).to_contain_text("Stopped")

    # PT: the slope field and what limits the speed
    jog.get_by_role("tab", name="Profile torque (PT)").click()
    jog.get_by_label("Torque slope (%/s)").fill("500")
    limit = page.get_by_test_id("jog-pt-speed-limit")
    expect(limit).to_contain_text("6080h Max motor speed")
    expect(limit).to_contain_text(re.compile(r"holds the speed at \d+ rpm"))
    shot(page, ".drive-jog", "drive_jog_pt.png")

    # every transition button through /drive/command: the state and the controlword it wrote
    buttons = page.get_by_role("group", name="State machine commands")
    for label, state, word in (
        ("Disable operation", "Switched on", 0x0007),
        ("Shutdown", "Ready to switch on", 0x0006),
        ("Switch on", "Switched on", 0x0007),
        ("Enable operation", "Operation enabled", 0x000F),
        ("Disable voltage", "Switch on disabled", 0x0000),
    ):
        buttons.get_by_role("button", name=label, exact=True).click()
        expect(page.get_by_test_id("drive-state")).to_have_text(state, timeout=5_000)
        assert drive_state(server, 3)["controlword"] == word, label


def api(server: str, method: str, path: str, body: object | None = None) -> object:
    data = None if body is None else json.dumps(body).encode()
    request = urllib.request.Request(
        f"{server}{path}", data=data, method=method, headers={"Content-Type": "application/json"}
    )
    with urllib.request.urlopen(request, timeout=5) as answer:
        result: object = json.load(answer)
        return result


def test_fault_is_reset_only_on_purpose_node_1(page: Page, server: str) -> None:
    """A faulted drive: Enable is refused naming the fault (nothing reset), the page offers
    "Reset fault, then enable" as two audited requests; a PP move stopped by a quick stop says
    so; the limits card says where the travel ends."""
    page.goto(f"{server}/nodes/1/drive")
    expect(page.get_by_test_id("state-diagram")).to_be_visible()
    enable(page)
    state = page.get_by_test_id("drive-state")
    # reading and enabling the MDi asks only for what its dictionary has: no abort on the timeline
    aborts = api(server, "GET", "/api/events?kind=sdo-abort&node=1&limit=100")
    assert isinstance(aborts, dict)
    assert [e["message"] for e in aborts["events"]] == []

    # MDi alarm 4 (following error) through the simulator's 5FF0h
    api(server, "PUT", "/api/nodes/1/sdo/5FF0/0", {"value": 4, "size": 4})
    expect(state).to_have_text("Fault")
    page.get_by_role("button", name="Enable", exact=True).click()
    why = page.get_by_role("alert", name="Why won't it enable?")
    expect(why).to_contain_text("fault 0x0004")
    expect(why).to_contain_text("send Fault reset")
    assert drive_state(server, 1)["state"] == "fault", "the refused enable reset nothing"
    shot(page, ".drive-machine", "drive_fault_why.png")
    why.get_by_role("button", name="Reset fault, then enable").click()
    expect(state).to_have_text("Operation enabled")
    expect(why).to_be_hidden()
    entries = api(server, "GET", "/api/audit?node=1&limit=20")
    assert isinstance(entries, list)
    acts = [(e["action"], e["result"]) for e in reversed(entries)]
    fault_acts = acts[-3:]
    assert fault_acts == [("drive-enable", "failed"), ("fault-reset", "ok"), ("drive-enable", "ok")]

    # a PP move stopped by a quick stop ends, with why
    jog = page.get_by_role("region", name="Jog")
    jog.get_by_role("tab", name="Profile position (PP)").click()
    jog.get_by_label("Position (rev)").fill("3")
    jog.get_by_role("button", name=re.compile(r"^Move by")).click()
    moved = page.get_by_test_id("pp-move")
    expect(moved).to_contain_text("moving")
    page.get_by_role("button", name="Quick stop node 1").click()
    expect(moved).to_contain_text("not reached — stopped by quick stop")
    shot(page, ".drive-jog", "drive_pp_interrupted.png")

    # where the travel ends: the simulator's switches at ±5 rev
    travel = page.get_by_role("table", name="Where the travel ends")
    expect(travel).to_contain_text("Limit switches")
    expect(travel).to_contain_text("simulator")
    expect(travel).to_contain_text("−5.000\u00a0rev\u00a0…\u00a05.000\u00a0rev")
    shot(page, ".drive-limits", "drive_limits_travel.png")
