"""A commissioning engineer's first steps, in Debian Chromium against the real app with the
three simulated drives: find the nodes, read and write the dictionary, change a parameter,
import vendor EDS files, save a parameter set and see what changed."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from playwright.sync_api import Page, expect

from tests.e2e.conftest import SHARED

EDS_FILES = sorted(
    path
    for path in (SHARED / "eds").iterdir()
    if path.suffix.lower() in {".eds", ".dcf", ".xdd", ".xpd"}
)


def open_entry(page: Page, server: str, node: int, search: str, name: str) -> None:
    page.goto(f"{server}/nodes/{node}/od")
    page.get_by_label("Search objects").fill(search)
    page.get_by_text(name, exact=True).first.click()
    expect(page.get_by_role("heading", name=name)).to_be_visible()


def test_scan_lists_the_three_simulated_drives(page: Page, server: str) -> None:
    page.goto(server)
    page.get_by_role("button", name="Scan", exact=True).click()
    table = page.get_by_role("table")
    for name in ("DVS_CANOPEN", "Kinco Servo", "C5-E-SIM"):
        expect(table.get_by_text(name, exact=True)).to_be_visible()
    expect(table.get_by_text("Pre-operational")).to_have_count(3)


def test_read_device_name_of_node_1(page: Page, server: str) -> None:
    open_entry(page, server, 1, "1008", "Manufacturer device name")
    page.get_by_role("button", name="Read", exact=True).click()
    expect(page.get_by_test_id("sdo-value")).to_have_text("DVS_CANOPEN")


def test_writing_the_statusword_shows_the_abort_code_and_meaning(page: Page, server: str) -> None:
    open_entry(page, server, 1, "6041", "Statusword")
    page.get_by_role("button", name="Write anyway…").click()
    page.get_by_label("New value").fill("6")
    page.get_by_role("button", name="Write", exact=True).click()
    expect(page.get_by_text("0x06010002")).to_be_visible()
    expect(page.get_by_text(re.compile("Attempt to write a read-only object"))).to_be_visible()


def test_changing_pa106_points_to_the_bitrate_wizard_and_is_pending(
    page: Page, server: str
) -> None:
    page.goto(f"{server}/nodes/1/parameters")
    page.get_by_label("PA-106", exact=True).select_option("4")
    page.get_by_role("button", name="Write PA-106").click()
    expect(
        page.get_by_text(re.compile("after a store and a reset.*use Change bitrate…"))
    ).to_be_visible()
    row = page.get_by_role("row").filter(has=page.get_by_role("rowheader", name="PA-106"))
    expect(row.get_by_text("pending until reset")).to_be_visible()


@pytest.mark.parametrize("eds", EDS_FILES, ids=lambda path: path.name)
def test_every_vendor_file_imports_with_its_report(page: Page, server: str, eds: Path) -> None:
    page.goto(f"{server}/tools")
    page.get_by_label("Choose EDS file to check…").set_input_files(str(eds))
    expect(page.get_by_text(eds.name).first).to_be_visible()
    expect(page.locator("dt:text-is('Objects') + dd")).to_have_text(re.compile(r"^[1-9]\d*$"))
    expect(page.get_by_text(re.compile(r"\d+ errors?, \d+ warnings?, \d+ notes?"))).to_be_visible()


def test_a_vendor_eds_becomes_the_nodes_dictionary(page: Page, server: str) -> None:
    page.goto(f"{server}/nodes/2/od")
    page.get_by_label("Load EDS…").set_input_files(str(SHARED / "eds" / "Kinco_KINCO-JDFD.EDS"))
    expect(page.get_by_text(re.compile("Kinco_KINCO-JDFD.EDS")).first).to_be_visible()
    page.get_by_role("button", name="Use profile dictionary").click()
    expect(page.get_by_text(re.compile("drive.eds")).first).to_be_visible()


def test_saved_dcf_shows_the_difference_after_a_change(
    page: Page, server: str, tmp_path: Path
) -> None:
    page.goto(f"{server}/nodes/3/parameters")
    with page.expect_download() as download:
        page.get_by_role("button", name="Save DCF").click()
    saved = tmp_path / "node3.dcf"
    download.value.save_as(saved)
    assert "[DeviceComissioning]" in saved.read_text()
    velocity = page.get_by_label("Profile velocity", exact=True)
    velocity.fill("4321")
    page.get_by_role("button", name="Write Profile velocity").click()
    expect(page.get_by_text(re.compile("applied|Applied"))).to_be_visible()
    page.get_by_role("button", name="Compare…").click()
    page.get_by_label(re.compile("DCF file to compare")).set_input_files(str(saved))
    page.get_by_role("button", name="Compare", exact=True).click()
    row = page.get_by_role("row", name=re.compile("Profile velocity 6081h:00"))
    expect(row).to_contain_text("4321")
    expect(row).to_have_class(re.compile("differs"))
