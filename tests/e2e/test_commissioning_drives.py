"""The whole commissioning flow on the Commission page, in Chromium, once per simulated drive
(node 1 MDi-S1-C, node 2 Kinco, node 3 CiA 402): from the Network page's scan to a record whose
nine steps all ran through their Run buttons and ended Done, then its PDF and HTML reports.

The three tests share one server (module-scoped), so record numbers grow from test to test:
headings are matched with a pattern. Full-page screenshots go to /tmp/commission_node<N>_*.png,
the PDF's pages to /tmp/commission_node<N>_pdf-*.png."""

from __future__ import annotations

import re
import subprocess
from dataclasses import dataclass
from pathlib import Path

import pytest
from playwright.sync_api import Locator, Page, ViewportSize, expect

STEP_RUN_MS = 90_000  # a step takes seconds; a loaded 2-core host takes longer
REPORT_MS = 60_000  # the PDF is rendered on request, plots and all

QUICK_STOP_DECELERATION = "6085/0"
SIM_NEG_LIMIT, SIM_POS_LIMIT = "5FF1/0", "5FF2/0"  # simulator only: limit switch positions
LIMIT_INCREMENTS = 200 * 131072  # ±200 rev of the simulated encoder: out of the way
GENTLE_RPM_S = 3000.0  # a quick stop ramp a real machine may have: 0.1 s from 300 rpm
USER_PER_REV = 100000  # the simulated drives' default gear: 100000 user units per rev
# 6085h in user units/s per ms: rpm/s ÷ 60 × units per rev ÷ 1000
GENTLE_6085 = round(GENTLE_RPM_S / 60 * USER_PER_REV / 1000)

VIEWPORT: ViewportSize = {"width": 1366, "height": 768}  # the page fixture's
MAX_SHOT_PX = 12_000  # a screenshot's height at most

HOMING_METHOD = "35"  # homing on the current position: over at once


@dataclass(frozen=True)
class Drive:
    node: int
    vendor_id: str  # as the report prints 1018h:01


DRIVES = {
    1: Drive(1, "0x00445653"),  # MDi-S1-C, "DVS"
    2: Drive(2, "0x00000300"),  # Kinco
    3: Drive(3, "0x0000026C"),  # CiA 402 (C5-E-SIM)
}

# (number, title) in the flow's order
STEPS = [
    (1, "Identity"),
    (2, "Communication"),
    (3, "Parameters"),
    (4, "PDO mapping"),
    (5, "Limits"),
    (6, "Stop test"),
    (7, "Test move"),
    (8, "Homing"),
    (9, "Store and verify"),
]
MOVING = {"Stop test", "Test move", "Homing"}


def shot(page: Page, node: int, what: str) -> None:
    """A full-page screenshot. The app's shell is one screen high and its main pane scrolls,
    so the window is made as tall as that pane's content for the shot, then set back."""
    viewport = page.viewport_size or VIEWPORT
    tall = page.evaluate(
        "() => Math.max(document.documentElement.scrollHeight,"
        " document.querySelector('.main')?.scrollHeight ?? 0)"
    )
    page.set_viewport_size(
        {"width": viewport["width"], "height": min(max(int(tall), viewport["height"]), MAX_SHOT_PX)}
    )
    try:
        page.screenshot(path=f"/tmp/commission_node{node}_{what}.png", full_page=True)
    finally:
        page.set_viewport_size(viewport)


def step(page: Page, number: int, title: str) -> Locator:
    return page.get_by_role("listitem", name=f"Step {number}: {title}")


def run(page: Page, number: int, title: str) -> Locator:
    """Run a step through its Run button; wait for its outcome (Done, Failed or a refused run)
    and fail with the step's reason if it did not end Done."""
    item = step(page, number, title)
    item.get_by_role("button", name=f"Run {title}", exact=True).click()
    badge = item.locator(".step-header .badge")
    ended = item.locator(".step-header .badge.step-done, .step-header .badge.step-failed")
    refused = item.locator(".step-actions ~ .error-text, .step-actions ~ .run-error")
    expect(ended.or_(refused).first).to_be_visible(timeout=STEP_RUN_MS)
    expect(item.locator(".step-running")).to_have_count(0, timeout=STEP_RUN_MS)
    status = badge.inner_text()
    if status != "Done":
        reasons = item.locator(".step-reason").all_inner_texts()
        errors = item.get_by_role("alert").all_inner_texts()
        pytest.fail(f"node step {number} {title} ended {status!r}: {reasons} {errors}")
    return item


def write(page: Page, server: str, node: int, entry: str, value: int) -> None:
    response = page.request.put(f"{server}/api/nodes/{node}/sdo/{entry}", data={"value": value})
    assert response.ok, f"write {entry} = {value} on node {node}: {response.text()}"


def pdf_text(path: Path) -> str:
    done = subprocess.run(
        ["pdftotext", "-layout", str(path), "-"], capture_output=True, text=True, check=True
    )
    return " ".join(done.stdout.split())  # words may wrap inside a table cell


def walk(page: Page, server: str, node: int, tmp_path: Path) -> None:
    drive = DRIVES[node]

    # the Network page: scan, the drive's name as shown there, into its Commission page
    page.goto(server)
    page.get_by_role("button", name="Scan", exact=True).click()
    nodes = page.get_by_role("table", name="Nodes")
    row = nodes.get_by_role("row").filter(
        has=page.get_by_role("link", name=f"Open node {node}", exact=True)
    )
    expect(row).to_be_visible()
    name_cell = row.locator("td").nth(1)
    expect(name_cell).not_to_have_text("—")
    name = name_cell.inner_text().strip()
    assert name, f"node {node} has no name on the Network page"
    shot(page, node, "network")
    page.get_by_role("link", name=f"Commission node {node}: no record yet").click()
    expect(page).to_have_url(f"{server}/nodes/{node}/commission")

    # start a record with the modes the page picks (PP and PV where the drive has them)
    expect(page.get_by_role("heading", name=f"Start commissioning node {node}")).to_be_visible()
    pp = page.get_by_role("checkbox", name=re.compile("PP Profile position"))
    expect(pp).to_be_checked()
    pv = page.get_by_role("checkbox", name=re.compile("PV Profile velocity"))
    if pv.count() and not pv.is_checked():
        pv.check()
    title = f"Axis {node}, e2e"
    page.get_by_role("textbox", name=re.compile("Title")).fill(title)
    shot(page, node, "start")
    page.get_by_role("button", name="Start record").click()
    heading = page.get_by_role("heading", name=re.compile(rf"^Record #\d+: {re.escape(title)}$"))
    expect(heading).to_be_visible()
    header = page.locator(".record-header")
    expect(header.locator(".badge")).to_have_text("In progress")
    expect(header).to_contain_text("0 of 9 steps done or skipped")
    shot(page, node, "new")

    # the record's change (written after it was made) and room for the moving steps
    write(page, server, node, SIM_NEG_LIMIT, -LIMIT_INCREMENTS)
    write(page, server, node, SIM_POS_LIMIT, LIMIT_INCREMENTS)
    write(page, server, node, QUICK_STOP_DECELERATION, GENTLE_6085)

    for number, step_title in STEPS:
        item = step(page, number, step_title)
        if step_title == "PDO mapping":
            item.get_by_role(
                "checkbox",
                name="Apply the manuals' recommended mapping for the record's modes first",
            ).check()
        if step_title == "Homing":
            method = item.get_by_role("combobox", name="Homing method")
            expect(method.locator(f"option[value='{HOMING_METHOD}']")).to_have_count(1)
            method.select_option(HOMING_METHOD)
        item = run(page, number, step_title)
        if step_title == "Identity":
            values = item.get_by_role("table", name="Values read (Identity)")
            vendor = values.get_by_role("row").filter(has_text="Vendor-ID")
            expect(vendor).to_contain_text(drive.vendor_id)
        if step_title == "Parameters":
            expect(item).to_contain_text("6085")
        if step_title in MOVING:
            expect(item.get_by_role("table", name=f"Figures of {step_title}")).to_be_visible()
            shot(page, node, step_title.lower().replace(" ", "_"))

    # the record: every step done
    expect(header.locator(".badge")).to_have_text("Done")
    expect(header).to_contain_text("9 of 9 steps done or skipped")
    expect(page.locator(".step-list .step-header .badge")).to_have_text(["Done"] * 9)
    expect(page.get_by_role("table", name="Figures of Stop test")).to_contain_text("stop time")
    expect(page.get_by_role("table", name="Figures of Test move")).to_contain_text("time to target")
    shot(page, node, "done")

    # the PDF report through the page's own link
    href = header.get_by_role("link", name="PDF", exact=True).get_attribute("href")
    assert href is not None
    assert href.startswith("/api/commissioning/"), href
    response = page.request.get(server + href, timeout=REPORT_MS)
    assert response.ok, response.text()
    assert response.headers["content-type"].startswith("application/pdf")
    pdf = tmp_path / "report.pdf"
    pdf.write_bytes(response.body())
    text = pdf_text(pdf)
    lowered = text.lower()
    assert name in text, f"{name!r} not in the PDF: {text[:2000]}"
    assert drive.vendor_id in text, f"{drive.vendor_id} not in the PDF: {text[:2000]}"
    for figure in ("stop time", "time to target", "homing time"):
        assert figure in lowered, f"{figure!r} not in the PDF"
    assert re.search(r"\b35\b", text), "homing method 35 not in the PDF"
    assert "TPDO1" in text, "the pdo step's live check is not in the PDF"
    assert "attained" in lowered, "the homing result is not in the PDF"
    assert title in text
    prefix = f"/tmp/commission_node{node}_pdf"
    for old in Path("/tmp").glob(f"commission_node{node}_pdf-*.png"):
        old.unlink()
    subprocess.run(["pdftoppm", "-png", "-r", "60", str(pdf), prefix], check=True)
    pages = sorted(Path("/tmp").glob(f"commission_node{node}_pdf-*.png"))
    assert len(pages) >= 2, pages

    # the HTML report names the drive
    with page.expect_popup() as popup_info:
        header.get_by_role("link", name="Report (HTML)").click()
    report = popup_info.value
    report.wait_for_load_state()
    body = report.locator("body")
    expect(body).to_contain_text(name, timeout=REPORT_MS)
    expect(body).to_contain_text(drive.vendor_id)
    expect(body).to_contain_text(title)
    report.close()


def test_commission_node_1_mdi_s1c(page: Page, server: str, tmp_path: Path) -> None:
    walk(page, server, 1, tmp_path)


def test_commission_node_2_kinco(page: Page, server: str, tmp_path: Path) -> None:
    walk(page, server, 2, tmp_path)


def test_commission_node_3_cia402(page: Page, server: str, tmp_path: Path) -> None:
    walk(page, server, 3, tmp_path)
