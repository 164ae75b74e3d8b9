"""PDO mapping in the browser: the wizard's PP mapping applied to node 1 (MDi-S1-C) as it is,
checked live on the bus, and edits the drive refuses, explained where they happen: in the
browser before asking (read-only object, fixed CAN id) and by the server (RTR transmission)."""

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
    # event-driven, and an event timer so a drive standing still still reports: the wizard's own
    expect(draft.get_by_label("TPDO1 event timer ms")).to_have_value("100")
    shot(page, "[data-testid=pdo-tpdo1]", "pdo_byte_layout.png")

    page.get_by_role("button", name="Validate").click()
    expect(page.get_by_text("Checked: no problems")).to_be_visible()
    load = page.get_by_test_id("bus-load")
    expect(load.get_by_role("heading", name="Bus load with the draft")).to_be_visible()
    expect(load.get_by_role("meter", name="Total bus load")).to_be_visible()
    # the server counts the master's event-driven RPDOs at the cycle given here
    load.get_by_label("Master cycle").fill("5")
    expect(load.get_by_role("row", name=re.compile(r"^RPDO1 "))).to_contain_text("200/s")
    shot(page, "[data-testid=bus-load]", "pdo_bus_load.png")

    page.get_by_role("button", name="Apply…").click()
    dialog = page.get_by_role("dialog")
    expect(dialog.get_by_text(re.compile(r"TPDO1"))).to_be_visible()
    expect(dialog.get_by_text("How node 1 takes the new mapping:")).to_be_visible()
    expect(dialog).to_contain_text("MDi-S1-C CANopen manual")
    shot(page, "[role=dialog]", "pdo_apply_confirm.png")
    dialog.get_by_role("button", name="Apply", exact=True).click()
    expect(page.get_by_text(re.compile("Read back from the device"))).to_be_visible()
    expect(page.get_by_role("region", name="Draft")).to_have_count(0)
    expect(tpdo1.get_by_text("100 ms", exact=True)).to_be_visible()  # the read-back's timer

    page.get_by_role("button", name="Start node and watch PDOs").click()
    sync = page.get_by_role("button", name="Produce SYNC")
    if sync.count():  # only a synchronous mapping needs SYNC
        sync.click()
    table = page.get_by_role("table", name="Received PDOs")
    row = table.get_by_role("row", name=re.compile(r"^0x181 TPDO1"))
    expect(row).to_contain_text("Statusword")
    expect(row).to_contain_text("Position actual value")
    expect(row.get_by_test_id("rate-385")).to_have_text(POSITIVE_RATE, timeout=10_000)
    expect(row.get_by_role("cell").nth(2)).to_have_text(re.compile(r"^(?:[3-9]|\d{2,})$"))
    # the Statusword in hex with its state in words, its bytes and number in the tooltip
    status = row.locator("dt", has_text="Statusword").locator("+ dd")
    expect(status).to_have_text(re.compile(r"^0x[0-9A-F]{4} · \S"))
    expect(status).to_have_attribute(
        "title", re.compile(r"^6041h:00 bytes: [0-9A-F]{2} [0-9A-F]{2} = \d+$")
    )
    # what the Drive page does with the RPDOs just mapped (event-driven: commands by RPDO)
    expect(page.get_by_test_id("pdo-drive-page")).to_contain_text("sends its commands by RPDO")
    # the master's RPDOs: a group of their own, nothing sent by a master in this test
    expect(table.get_by_role("rowgroup", name="Sent by the master")).to_contain_text(
        "None seen from the master: RPDO1 (0x201)"
    )
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

    # refused in the browser too: the MDi-S1-C fixes the CAN ids of PDOs 1-4 (the server's rules)
    tpdo1 = page.get_by_role("region", name="TPDO1 draft")
    cob_id = tpdo1.get_by_label("TPDO1 COB-ID")
    expect(cob_id).not_to_be_editable()
    cob_id.press("2")
    expect(tpdo1.get_by_role("alert")).to_have_text(
        "This drive fixes the CAN id of PDOs 1–4 to the pre-defined set; only the valid bit can"
        " change."
    )
    expect(cob_id).to_have_value("0x181")

    # refused by the server: the MDi-S1-C has no RTR-triggered PDOs
    transmission = tpdo1.get_by_label("TPDO1 transmission type")
    transmission.fill("253")
    page.get_by_role("button", name="Apply…").click()
    page.get_by_role("dialog").get_by_role("button", name="Apply", exact=True).click()
    result = page.get_by_role("alert", name="Apply result")
    expect(result).to_contain_text("Not applied")
    # the problem names 1800h:02: it is shown at the transmission type field
    expect(transmission).to_have_attribute("aria-invalid", "true")
    expect(tpdo1.get_by_role("list", name="TPDO1 parameter problems")).to_contain_text(
        "remote request"
    )
    shot(page, "[aria-label='Apply result']", "pdo_apply_failure.png")
    shot(page, "[data-testid=pdo-tpdo1]", "pdo_apply_failure_tpdo1.png")
