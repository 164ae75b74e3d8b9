"""Faults and field diagnostics in Chromium against the simulated drives: alarm 4 injected on
node 1 (the simulator's 5FF0h) is decoded on the node's Faults tab and in the banner on every
page, shows on the timeline, and goes away with the fault reset; a recording of the live bus
(SDO reads and an NMT command) uploaded on the Logs page gives its plain-language summary;
the Logs page records and downloads by itself. Element screenshots go to build/screenshots."""

from __future__ import annotations

import re
from pathlib import Path

import can
from playwright.sync_api import Page, expect

from tests.e2e.conftest import SCREENSHOTS


def shot(page: Page, selector: str, name: str) -> None:
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    element = page.locator(selector).first
    element.scroll_into_view_if_needed()
    element.screenshot(path=str(SCREENSHOTS / name))


def test_an_injected_alarm_is_decoded_shown_everywhere_and_reset(page: Page, server: str) -> None:
    page.goto(f"{server}/nodes/1/faults")
    expect(page.get_by_role("heading", name="No active fault")).to_be_visible()
    injected = page.request.put(f"{server}/api/nodes/1/sdo/5FF0/0", data={"value": 4})
    assert injected.ok, injected.text()

    banner = page.get_by_role("alert", name="Nodes in fault")
    expect(banner).to_contain_text("Node 1 in fault: alarm 4 位置超差")
    active = page.locator(".fault-active")
    expect(active.get_by_role("heading")).to_contain_text("In fault: alarm 4 位置超差")
    expect(active).to_contain_text("the drive's own alarm table")
    expect(active).to_contain_text("MDi-S1-C CANopen manual §4.1")
    expect(active).to_contain_text("04 00")  # the 2-byte EMCY: the alarm number
    expect(active).to_contain_text(re.compile(r"603Fh on the drive: 0x0004: alarm 4"))
    history = page.get_by_role("table", name="Fault history")
    expect(history.get_by_role("row").nth(1)).to_contain_text("alarm 4")
    # MDi-S1-C has no 1003h: said in words, not as an error
    expect(page.get_by_text("Node 1 keeps no error history of its own (no 1003h).")).to_be_visible()
    shot(page, ".fault-banner", "faults-banner.png")
    shot(page, ".faults-page", "faults-tab.png")

    # the banner is on every page and leads to the node's Faults tab
    page.goto(f"{server}/tools")
    page.get_by_role("link", name="Open node 1 faults").click()
    expect(page).to_have_url(f"{server}/nodes/1/faults")

    # the timeline on the Network page has the EMCY, and filters by kind
    page.goto(server)
    page.get_by_label("Kind").select_option("emcy")
    expect(page.get_by_role("table", name="Timeline")).to_contain_text("alarm 4 位置超差")
    shot(page, "section[aria-labelledby=events-heading]", "faults-timeline.png")

    page.goto(f"{server}/nodes/1/faults")
    page.locator(".fault-active").get_by_role("button", name="Fault reset").click()
    expect(page.get_by_role("status").filter(has_text="fault reset: node 1")).to_contain_text(
        "went from Fault to"
    )
    expect(page.get_by_role("heading", name="No active fault")).to_be_visible()
    expect(banner).to_have_count(0)
    expect(page.locator(".fault-active")).to_contain_text("0x0000: no error")


def test_a_recorded_log_is_summarised(page: Page, server: str, tmp_path: Path) -> None:
    started = page.request.post(f"{server}/api/recording", data={"format": "log"})
    assert started.ok, started.text()
    for index in ("1018/1", "1018/2", "1008/0"):
        assert page.request.get(f"{server}/api/nodes/2/sdo/{index}").ok
    assert page.request.post(f"{server}/api/nodes/2/nmt", data={"command": "start"}).ok
    page.wait_for_timeout(300)  # a few heartbeats after the command
    stopped = page.request.delete(f"{server}/api/recording")
    assert stopped.ok, stopped.text()
    recorded = tmp_path / "bus.log"
    recorded.write_bytes(stopped.body())
    page.request.post(f"{server}/api/nodes/2/nmt", data={"command": "pre-operational"})

    page.goto(f"{server}/logs")
    page.get_by_label("Choose CAN log…").set_input_files(str(recorded))
    summary = page.get_by_role("list", name="Summary")
    expect(summary).to_contain_text(re.compile(r"frames over \d+\.\d+ s"))
    expect(summary).to_contain_text("node 2")
    expect(page.get_by_label("Log totals")).to_contain_text("Frames")
    # the recording holds the whole bus, the tool's own frames included: its NMT command too
    expect(page.get_by_role("table", name="Decoded events").get_by_role("row")).not_to_have_count(0)
    assert any(m.arbitration_id == 0x000 for m in can.LogReader(recorded))  # NMT start
    csv = page.request.get(f"{server}{page.get_by_role('link', name='CSV').get_attribute('href')}")
    assert csv.ok
    assert b"seq" in csv.body()[:200]
    shot(page, ".log-result", "logs-summary.png")

    # recording from the page itself: start, it counts, stop downloads the file
    page.get_by_label("Format").select_option("asc")
    page.get_by_role("button", name="Start recording").click()
    expect(page.get_by_text(re.compile(r"^Recording ASC: \d[\d,]* frames"))).to_be_visible()
    with page.expect_download() as download:
        page.get_by_role("button", name="Stop and download").click()
    assert download.value.suggested_filename.endswith(".asc")
    expect(page.get_by_text("Not recording")).to_be_visible()
    shot(page, "section[aria-labelledby=recording-heading]", "logs-recording.png")
    page.get_by_role("button", name="Analyse this recording").click()
    expect(
        page.get_by_role("heading", name=re.compile(r"^Summary of servodesk-.*\.asc$"))
    ).to_be_visible()


def test_a_cia301_emcy_and_the_drives_own_history(page: Page, server: str) -> None:
    injected = page.request.put(f"{server}/api/nodes/3/sdo/5FF0/0", data={"value": 0x8611})
    assert injected.ok, injected.text()
    page.goto(f"{server}/nodes/3/faults")
    active = page.locator(".fault-active")
    expect(active.get_by_role("heading")).to_contain_text("In fault: 0x8611")
    expect(active).to_contain_text("generic")  # the error register 1001h in words
    expect(active).to_contain_text("11 86")
    history = page.get_by_role("table", name="Drive's error history")
    expect(history).to_contain_text("0x8611")
    shot(page, ".faults-page", "faults-tab-cia402.png")

    page.get_by_role("button", name="Clear history…").click()
    dialog = page.get_by_role("dialog")
    expect(dialog).to_contain_text("cannot be undone")
    dialog.get_by_role("button", name="Clear 1003h").click()
    expect(page.get_by_text("node 3: error history 1003h cleared")).to_be_visible()
    expect(page.get_by_text("The drive's history is empty.")).to_be_visible()

    active.get_by_role("button", name="Fault reset").click()
    expect(page.get_by_role("heading", name="No active fault")).to_be_visible()
    expect(page.get_by_role("alert", name="Nodes in fault")).to_have_count(0)


def test_the_tab_that_controls_the_drive_resets_its_fault(page: Page, server: str) -> None:
    """Control taken on the Drive page (enable) is this tab's on the Faults tab too: its reset
    goes through, where it was refused as another client's."""
    page.goto(f"{server}/nodes/1/drive")
    page.get_by_role("button", name="Enable", exact=True).click()
    expect(page.get_by_text("You control this drive")).to_be_visible()
    injected = page.request.put(f"{server}/api/nodes/1/sdo/5FF0/0", data={"value": 4})
    assert injected.ok, injected.text()
    page.get_by_role("link", name="Faults").first.click()  # the same page load: the same tab
    active = page.locator(".fault-active")
    expect(active.get_by_role("heading")).to_contain_text("In fault: alarm 4")
    active.get_by_role("button", name="Fault reset").click()
    expect(page.get_by_role("status").filter(has_text="fault reset: node 1")).to_contain_text(
        "went from Fault to"
    )
    expect(page.get_by_role("heading", name="No active fault")).to_be_visible()
