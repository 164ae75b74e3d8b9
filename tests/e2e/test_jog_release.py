"""A released torque jog in Chromium (node 3, CiA 402): 2 % torque held 0.3 s runs an unloaded
axis up to hundreds of rpm; after the release the page says "Stopping" while it moves and
"Stopped" only at rest, the axis stands within the distance the drive's quick stop ramp needs
and the drive stays enabled. Then ServoDesk's own speed cap stops a held torque jog, and the
page says why."""

from __future__ import annotations

import re
import time

from playwright.sync_api import Page, expect

from tests.e2e.test_drive import api, drive_state, enable, sdo_value, shot, velocity

NODE = 3
REST_RPM = 5.0
USER_PER_REV = 100_000  # node 3: 6091h 131072 : 100000
QUICK_STOP_2000_RPM_S = 3333  # 6085h in user units/s/ms (100 000 per revolution)
SIM_LIMIT_SWITCHES = ((0x5FF1, -1000), (0x5FF2, 1000))  # revolutions
SPEED = re.compile(r"(-?[\d\s]+(?:\.\d+)?) rpm")


def page_speed(text: str) -> float:
    found = SPEED.search(text)
    assert found is not None, text
    return abs(float(found.group(1).replace(" ", "").replace("\u202f", "")))


def press(page: Page, name: re.Pattern[str]) -> None:
    """Press (and keep pressed) a hold-to-run button of the jog area."""
    button = page.get_by_role("region", name="Jog").get_by_role("button", name=name)
    box = button.bounding_box()
    assert box is not None
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.down()


def hold(page: Page, server: str, name: re.Pattern[str], seconds: float) -> tuple[float, float]:
    """Hold the button `seconds` once the jog runs; speed and position just before release."""
    press(page, name)
    expect(page.get_by_test_id("jog-pt-status")).to_contain_text("Moving")
    page.wait_for_timeout(seconds * 1000)
    speed, where = velocity(server, NODE), position_rev(server, NODE)
    page.mouse.up()
    return speed, where


def position_rev(server: str, node: int) -> float:
    """6064h read from the drive now, in revolutions (node 3: 100 000 user units per rev)."""
    return sdo_value(server, node, 0x6064) / USER_PER_REV


def test_a_released_torque_jog_reads_stopping_until_the_axis_is_at_rest(
    page: Page, server: str
) -> None:
    page.goto(f"{server}/nodes/{NODE}/drive")
    expect(page.get_by_test_id("state-diagram")).to_be_visible()
    enable(page)
    jog = page.get_by_role("region", name="Jog")
    jog.get_by_role("tab", name="Profile torque (PT)").click()
    jog.get_by_label("Torque (%)").fill("2")
    limit = drive_state(server, NODE)["limits"]
    assert isinstance(limit, dict)
    jog.get_by_label("Speed cap (rpm)").fill(str(int(limit["max_velocity_rpm"])))
    # a gentle quick stop ramp, as many machines have (2000 rpm/s; the simulation's default
    # stops in milliseconds, too fast to see the page say anything in between)
    api(server, "PUT", f"/api/nodes/{NODE}/sdo/6085/0", {"value": QUICK_STOP_2000_RPM_S})
    for index, rev in SIM_LIMIT_SWITCHES:  # the simulation's switches out of the way
        api(server, "PUT", f"/api/nodes/{NODE}/sdo/{index:04X}/0", {"value": rev * 131072})

    released_at, position = hold(page, server, re.compile(r"^Hold \+2 %"), 0.3)
    status = page.get_by_test_id("jog-pt-status")
    said: list[tuple[str, float]] = []
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        text = status.text_content() or ""
        said.append((text, velocity(server, NODE)))
        if text.startswith("Stopped") and len(said) > 1:
            break
        page.wait_for_timeout(30)
    assert abs(released_at) > 50, f"the torque jog did not move the axis ({released_at} rpm)"
    assert any(text.startswith("Stopping") for text, _ in said), said
    for text, _rpm in said:
        if text.startswith("Stopped"):
            assert page_speed(text) < REST_RPM, f"the page said {text!r} while moving: {said}"
    assert said[-1][0].startswith("Stopped"), said[-5:]
    expect(status).to_contain_text("Stopped")
    end = drive_state(server, NODE)
    assert abs(velocity(server, NODE)) < REST_RPM
    assert end["state"] == "operation_enabled", end["fault"]  # braked, not faulted
    # the distance a 2000 rpm/s ramp needs from the release speed, plus 0.3 s of latency
    rev_s = abs(released_at) / 60
    allowed = rev_s**2 / (2 * 2000 / 60) + rev_s * 0.3 + 0.5
    travelled = abs(position_rev(server, NODE) - position)
    assert travelled < allowed, f"{travelled:.2f} rev after the release (allowed {allowed:.2f})"
    shot(page, ".drive-jog", "drive_jog_pt_released.png")


def test_servodesk_s_speed_cap_stops_a_held_torque_jog(page: Page, server: str) -> None:
    page.goto(f"{server}/nodes/{NODE}/drive")
    expect(page.get_by_test_id("state-diagram")).to_be_visible()
    if drive_state(server, NODE)["state"] != "operation_enabled":
        enable(page)
    jog = page.get_by_role("region", name="Jog")
    jog.get_by_role("tab", name="Profile torque (PT)").click()
    jog.get_by_label("Torque (%)").fill("2")
    jog.get_by_label("Speed cap (rpm)").fill("100")
    press(page, re.compile(r"^◀ Hold −2 %"))
    try:
        # said once, where the hold ended: "Stopped by the server: speed cap 100 rpm passed …"
        expect(jog.get_by_role("alert")).to_contain_text("speed cap 100 rpm passed", timeout=5_000)
        expect(page.get_by_test_id("jog-pt-status")).to_contain_text("Stopped", timeout=5_000)
    finally:
        page.mouse.up()
    assert abs(velocity(server, NODE)) < REST_RPM
    shot(page, ".drive-jog", "drive_jog_pt_speed_cap.png")
