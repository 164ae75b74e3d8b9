"""PDO mapping in the browser: the wizard's PP mapping applied to node 1 (MDi-S1-C), checked
live on the bus, and an apply the drive refuses, explained where it happened."""

from __future__ import annotations

import re

from playwright.sync_api import Page, expect

from tests.e2e.conftest import SCREENSHOTS

# A rate in the live table: "48/s", "9.5/s"; not "0.0/s".
POSITIVE_RATE = re.compile(r"^(?:[1-9]\d*(?:\.\d)?|0\.[1-9])/s$")


def shot(page: Page, locator_name: str, name: str) -> None:
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    page.locator(locator_name).first.scroll_into_view_if_needed()
    page.locator(locator_name).first.screenshot(path=str(SCREENSHOTS / name))


def test_pp_mapping_is_applied_and_seen_live(page: Page, server: str) -> None:
    page.goto(f"{server}/nodes/1/pdos")
    tpdo1 = page.get_by_role("region", name="TPDO1", exact=True)
    expect(tpdo1.get_by_role("list", name="TPDO1 frame")).to_be_visible()
    shot(page, "[data-testid=pdo-tpdo1]", "pdo_byte_layout_device.png")

    # the wizard: Profile position is preselected
    expect(page.get_by_label("Profile position (PP)")).to_be_checked()
    page.get_by_role("button", name="Recommend mapping").click()
    draft = page.get_by_role("region", name="TPDO1 draft")
    frame = draft.get_by_role("list", name="TPDO1 frame", exact=True)
    expect(frame.get_by_role("listitem").first).to_have_attribute(
        "aria-label", re.compile(r"^Statusword \(6041h:00, 16 bit")
    )
    expect(frame.get_by_role("listitem", name=re.compile("^Position actual value"))).to_be_visible()
    # a drive standing still changes nothing: let the event timer send TPDO1 every 20 ms
    draft.get_by_label("TPDO1 event timer ms").fill("20")
    expect(draft.get_by_text(re.compile("event timer 0 → 20 ms"))).to_be_visible()
    shot(page, "[data-testid=pdo-tpdo1]", "pdo_byte_layout.png")

    page.get_by_role("button", name="Validate").click()
    expect(page.get_by_text("Checked: no problems")).to_be_visible()
    load = page.get_by_test_id("bus-load")
    expect(load.get_by_role("heading", name="Bus load with the draft")).to_be_visible()
    expect(load.get_by_role("meter", name="Total bus load")).to_be_visible()
    shot(page, "[data-testid=bus-load]", "pdo_bus_load.png")

    page.get_by_role("button", name="Apply…").click()
    dialog = page.get_by_role("dialog")
    expect(dialog.get_by_text(re.compile(r"TPDO1"))).to_be_visible()
    dialog.get_by_role("button", name="Apply", exact=True).click()
    expect(page.get_by_text(re.compile("Read back from the device"))).to_be_visible()
    expect(page.get_by_role("region", name="Draft")).to_have_count(0)
    expect(tpdo1.get_by_text("20 ms")).to_be_visible()  # the read-back's event timer

    page.get_by_role("button", name="Start node and watch PDOs").click()
    sync = page.get_by_role("button", name="Produce SYNC")
    if sync.count():  # only a synchronous mapping needs SYNC
        sync.click()
    row = page.get_by_role("table", name="Received PDOs").get_by_role(
        "row", name=re.compile(r"^0x181 TPDO1")
    )
    expect(row).to_contain_text("Statusword")
    expect(row).to_contain_text("Position actual value")
    expect(row.get_by_test_id("rate-385")).to_have_text(POSITIVE_RATE, timeout=10_000)
    expect(row.get_by_role("cell").nth(2)).to_have_text(re.compile(r"^(?:[3-9]|\d{2,})$"))
    shot(page, "section[aria-labelledby=pdo-live-heading]", "pdo_live_check.png")
    page.get_by_role("button", name="Stop watching").click()


def test_an_apply_the_drive_refuses_is_explained(page: Page, server: str) -> None:
    page.goto(f"{server}/nodes/1/pdos")
    page.get_by_role("button", name="Edit current mapping").click()
    rpdo1 = page.get_by_role("region", name="RPDO1 draft")

    # refused in the browser before asking the server: an RPDO writes, 6064h is read-only
    rpdo1.get_by_label("Find an object to map into RPDO1").fill("6064")
    rpdo1.get_by_role("button", name="Add Position actual value 6064h:00").click()
    expect(rpdo1.get_by_role("alert")).to_contain_text("is read-only")

    # refused by the server: the MDi-S1-C fixes the CAN-IDs of PDOs 1-4
    tpdo1 = page.get_by_role("region", name="TPDO1 draft")
    tpdo1.get_by_label("TPDO1 COB-ID").fill("0x281")
    page.get_by_role("button", name="Apply…").click()
    page.get_by_role("dialog").get_by_role("button", name="Apply", exact=True).click()
    result = page.get_by_role("alert", name="Apply result")
    expect(result).to_contain_text("Not applied")
    expect(tpdo1.get_by_role("list", name="TPDO1 problems")).to_contain_text("cannot be set")
    shot(page, "[aria-label='Apply result']", "pdo_apply_failure.png")
    shot(page, "[data-testid=pdo-tpdo1]", "pdo_apply_failure_tpdo1.png")
