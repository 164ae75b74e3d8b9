"""The Commission page in Chromium against the simulated drives: from the Network page's node
list to node 3's guided flow: start a record, run the automated reads, sign off the PDO step,
skip homing with a reason, prove the store over a reset, see the statuses, open the report.
Full-page screenshots go to /tmp/commission_*.png."""

from __future__ import annotations

import re

from playwright.sync_api import Locator, Page, expect

STEP_RUN_MS = 90_000  # a step takes seconds; a loaded 2-core host takes longer


def step(page: Page, number: int, title: str) -> Locator:
    return page.get_by_role("listitem", name=f"Step {number}: {title}")


def run(page: Page, number: int, title: str) -> Locator:
    item = step(page, number, title)
    item.get_by_role("button", name=f"Run {title}").click()
    expect(item.locator(".step-header .badge")).to_have_text("Done", timeout=STEP_RUN_MS)
    return item


def test_commission_node_3_from_the_network_page_to_the_report(page: Page, server: str) -> None:
    page.goto(server)
    page.get_by_role("button", name="Scan", exact=True).click()
    nodes = page.get_by_role("table", name="Nodes")
    expect(nodes.get_by_text("C5-E-SIM", exact=True)).to_be_visible()
    page.get_by_role("link", name="Commission node 3: no record yet").click()
    expect(page).to_have_url(f"{server}/nodes/3/commission")

    expect(page.get_by_role("heading", name="Start commissioning node 3")).to_be_visible()
    expect(page.get_by_role("checkbox", name=re.compile("PP Profile position"))).to_be_checked()
    page.get_by_role("textbox", name=re.compile("Title")).fill("Axis X, e2e")
    page.screenshot(path="/tmp/commission_start.png", full_page=True)
    page.get_by_role("button", name="Start record").click()
    expect(page.get_by_role("heading", name="Record #1: Axis X, e2e")).to_be_visible()
    page.screenshot(path="/tmp/commission_new.png", full_page=True)

    identity = run(page, 1, "Identity")
    values = identity.get_by_role("table", name="Values read (Identity)")
    expect(values.get_by_role("row").filter(has_text="Vendor-ID")).to_contain_text("0x0000026C")
    run(page, 2, "Communication")
    run(page, 5, "Limits")

    pdo = step(page, 4, "PDO mapping")
    pdo.get_by_role("button", name="Sign off PDO mapping").click()
    expect(pdo.locator(".step-header .badge")).to_have_text("Done")

    homing = step(page, 8, "Homing")
    homing.get_by_role("button", name="Skip Homing…").click()
    expect(homing.get_by_role("button", name="Skip step")).to_be_disabled()
    homing.get_by_role("textbox", name="Reason to skip Homing").fill("absolute encoder")
    homing.get_by_role("button", name="Skip step").click()
    expect(homing.locator(".step-header .badge")).to_have_text("Skipped")
    expect(homing).to_contain_text("Reason: absolute encoder")

    verify = step(page, 9, "Store and verify")
    verify.get_by_role("button", name="Run Store and verify").click()
    expect(verify.locator(".step-header .badge")).to_have_text(
        re.compile("Done|Failed"), timeout=STEP_RUN_MS
    )
    expect(verify.locator(".step-header .badge")).to_have_text("Done")

    # parameters, stop test and test move are still to do: the record is in progress
    header = page.locator(".record-header")
    expect(header.locator(".badge")).to_have_text("In progress")
    expect(header).to_contain_text("6 of 9 steps done or skipped")
    badges = page.locator(".step-list .step-header .badge")
    expect(badges).to_have_text(
        ["Done", "Done", "To do", "Done", "Done", "To do", "To do", "Skipped", "Done"]
    )
    page.screenshot(path="/tmp/commission_steps.png", full_page=True)
    page.set_viewport_size({"width": 1366, "height": 768})
    identity.scroll_into_view_if_needed()
    page.screenshot(path="/tmp/commission_identity.png")

    with page.expect_popup() as popup_info:
        page.get_by_role("link", name="Report (HTML)").click()
    report = popup_info.value
    report.wait_for_load_state()
    expect(report.locator("body")).to_contain_text("C5-E-SIM")
    expect(report.locator("body")).to_contain_text("0x0000026C")
    report.close()

    page.goto(server)
    chip = page.get_by_role("link", name="Commissioning of node 3: record #1")
    expect(chip).to_have_text("In progress")
    expect(page.get_by_role("link", name="Commission node 1: no record yet")).to_have_text("—")
    page.screenshot(path="/tmp/commission_network.png", full_page=True)

    # back through the chip; the test move runs for seconds and shows that it runs
    chip.click()
    move = step(page, 7, "Test move")
    expect(move.get_by_role("note", name="The axis will move")).to_contain_text("quick stop")
    move.get_by_role("button", name="Run Test move").click()
    expect(move.get_by_role("status").filter(has_text="Running the test move")).to_be_visible()
    move.scroll_into_view_if_needed()
    page.screenshot(path="/tmp/commission_running.png")
    expect(move.locator(".step-header .badge")).to_have_text(
        re.compile("Done|Failed"), timeout=STEP_RUN_MS
    )
    expect(move.get_by_role("table", name="Figures of Test move")).to_contain_text("time to target")
    move.scroll_into_view_if_needed()
    page.screenshot(path="/tmp/commission_test_move.png")
