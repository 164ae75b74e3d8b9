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


def velocity(server: str, node: int) -> float:
    value = drive_state(server, node)["velocity_rpm"]
    assert isinstance(value, int | float)
    return float(value)


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
    page.mouse.up()
    assert moving > 50, f"the axis should turn while held (velocity {moving} rpm)"
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
