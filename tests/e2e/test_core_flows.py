"""What a new user meets in the core, in Debian Chromium against the real app with the three
simulated drives: a parameter set is written only after the user saw what changes, restored
defaults can be activated right there, the bitrate dialog offers what the drive supports, a
Stopped node says so with the way out, events survive a reload, a flooding heartbeat asks."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from playwright.sync_api import Page, expect


def entry(page: Page, server: str, node: int, index: str) -> Any:
    response = page.request.get(f"{server}/api/nodes/{node}/sdo/{index}/0")
    assert response.ok, response.text()
    return response.json()["value"]


def test_loading_a_dcf_shows_the_changes_and_writes_only_after_confirming(
    page: Page, server: str, tmp_path: Path
) -> None:
    page.goto(f"{server}/nodes/3/parameters")
    with page.expect_download() as download:
        page.get_by_role("button", name="Save DCF").click()
    saved = tmp_path / "node3.dcf"
    download.value.save_as(saved)
    saved_velocity = entry(page, server, 3, "6081")
    velocity = page.get_by_label("Profile velocity", exact=True)
    velocity.fill("4321")
    page.get_by_role("button", name="Write Profile velocity").click()
    expect(page.get_by_text(re.compile("applied|Applied"))).to_be_visible()

    page.get_by_label("Load DCF…").set_input_files(str(saved))
    dialog = page.get_by_role("dialog")
    expect(dialog).to_contain_text("Nothing has been written yet")
    change = dialog.get_by_role("row", name=re.compile("Profile velocity 6081h:00"))
    expect(change).to_contain_text("4321")
    expect(change).to_contain_text(str(saved_velocity))
    assert entry(page, server, 3, "6081") == 4321  # picking the file wrote nothing

    dialog.get_by_role("button", name=re.compile(r"^Write \d+ values?$")).click()
    expect(page.get_by_text(re.compile(r"Written \d+, skipped \d+, failed 0"))).to_be_visible()
    assert entry(page, server, 3, "6081") == saved_velocity
    # the comparison is the node after the load: nothing differs from the file any more
    expect(page.get_by_text(re.compile(r"^0 of \d+ entries differ from the file"))).to_be_visible()


def test_a_set_from_another_drive_needs_an_explicit_yes(
    page: Page, server: str, tmp_path: Path
) -> None:
    mdi_set = tmp_path / "node1.dcf"
    mdi_set.write_text(page.request.get(f"{server}/api/nodes/1/dcf").text())
    page.goto(f"{server}/nodes/3/parameters")
    page.get_by_label("Load DCF…").set_input_files(str(mdi_set))
    dialog = page.get_by_role("dialog")
    expect(dialog.get_by_role("alert")).to_contain_text("This file is for another device")
    write = dialog.get_by_role("button", name=re.compile("^Write"))
    expect(write).to_be_disabled()
    dialog.get_by_role("button", name="Cancel").click()
    expect(page.get_by_role("dialog")).to_have_count(0)


def test_restored_defaults_take_effect_with_the_reset_offered_there(
    page: Page, server: str
) -> None:
    page.goto(f"{server}/nodes/1/parameters")
    speed = page.get_by_label("PA-103", exact=True)
    speed.fill("3000")
    page.get_by_role("button", name="Write PA-103").click()
    expect(page.get_by_text("PA-103: applied")).to_be_visible()
    page.get_by_role("button", name="Store parameters").click()
    page.get_by_role("dialog").get_by_role("button", name="Store", exact=True).click()

    page.get_by_role("button", name="Restore defaults").click()
    page.get_by_role("dialog").get_by_role("button", name="Restore defaults").click()
    notice = page.get_by_role("status", name="Restored defaults")
    expect(notice).to_contain_text("take effect after a reset")
    expect(speed).to_have_value("3000")  # not yet: the drive runs the old values until reset

    notice.get_by_role("button", name="Reset node 1 now").click()
    page.get_by_role("dialog").get_by_role("button", name="Reset node").click()
    expect(page.get_by_text(re.compile("Node 1 was reset and answers again"))).to_be_visible(
        timeout=15_000
    )
    expect(speed).to_have_value("6000")


def test_the_bitrate_dialog_offers_what_each_drive_supports(page: Page, server: str) -> None:
    page.goto(f"{server}/nodes/2/parameters")
    page.get_by_role("button", name="Change bitrate…").click()
    dialog = page.get_by_role("dialog")
    options = dialog.get_by_label("New bitrate").locator("option")
    expect(options).to_have_count(6)
    texts = options.all_inner_texts()
    assert not any(text.startswith("800") for text in texts)
    expect(dialog).to_contain_text("supports 1000, 500, 250, 125, 50, 20 kbit/s")
    dialog.get_by_role("button", name="Cancel").click()

    page.goto(f"{server}/nodes/3/parameters")
    page.get_by_role("button", name="Change bitrate…").click()
    dialog = page.get_by_role("dialog")
    expect(dialog).to_contain_text("sets its bitrate outside CANopen")
    expect(dialog.get_by_role("button", name="Change bitrate")).to_have_count(0)


def test_a_stopped_node_says_so_and_offers_the_way_out(page: Page, server: str) -> None:
    stop = page.request.post(f"{server}/api/nodes/3/nmt", data={"command": "stop"})
    assert stop.ok, stop.text()
    page.goto(f"{server}/nodes/3/parameters")
    alert = page.get_by_role("alert").filter(has_text="node 3 is Stopped")
    expect(alert).to_contain_text("SDO is not available in that state")
    alert.get_by_role("button", name="Set node 3 Pre-operational").click()
    expect(page.get_by_label("Profile velocity", exact=True)).to_be_visible()


def test_events_survive_a_reload(page: Page, server: str) -> None:
    page.goto(server)
    for command in ("stop", "start"):
        sent = page.request.post(f"{server}/api/nodes/2/nmt", data={"command": command})
        assert sent.ok
    expect(page.get_by_text("NMT start sent to node 2").first).to_be_visible()
    page.reload()
    expect(page.get_by_text("NMT stop sent to node 2").first).to_be_visible()
    expect(page.get_by_text("NMT start sent to node 2").first).to_be_visible()
    page.request.post(f"{server}/api/nodes/2/nmt", data={"command": "pre-operational"})


def test_a_flooding_heartbeat_asks_first(page: Page, server: str) -> None:
    page.goto(server)
    field = page.get_by_label("Heartbeat producer time of node 3 (ms)")
    field.fill("5")
    field.press("Enter")
    expect(page.get_by_text(re.compile("puts 200 frames/s on the bus"))).to_be_visible()
    assert entry(page, server, 3, "1017") != 5
    page.get_by_role("button", name="Set anyway").click()
    expect(field).to_have_value("5")
    assert entry(page, server, 3, "1017") == 5
    field.fill("100")
    field.press("Enter")
    expect(field).to_have_value("100")
