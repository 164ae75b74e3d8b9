"""A drive re-addressed by its own parameter (MDi PA-105 = 5, store, reset) in Chromium: the
Network page says node 1 is gone and where its drive answers now, Forget takes it off the list,
and the node-id wizard brings the drive back to 1 (the bus decides, not the list). A drive the
wizard cannot re-address says so when the dialog opens."""

from __future__ import annotations

from playwright.sync_api import Page, expect


def test_a_readdressed_drive_leaves_a_ghost_that_is_named_and_forgotten(
    page: Page, server: str
) -> None:
    for request in (
        ("put", "/api/nodes/1/params/PA-105", {"value": 5}),
        ("post", "/api/nodes/1/store", {"confirm": True}),
        ("post", "/api/nodes/1/nmt", {"command": "reset-node"}),
    ):
        method, path, body = request
        answer = getattr(page.request, method)(f"{server}{path}", data=body)
        assert answer.ok, answer.text()
    page.goto(server)
    nodes = page.get_by_role("table", name="Nodes")
    expect(nodes.get_by_role("link", name="Open node 5")).to_be_visible()  # its boot-up
    page.get_by_role("button", name="Scan", exact=True).click()
    expect(nodes).to_contain_text("Gone: the drive answers as node 5 now.")
    page.get_by_role("button", name="Forget node 1").click()
    expect(nodes.get_by_role("link", name="Open node 1")).to_have_count(0)

    page.goto(f"{server}/nodes/5/parameters")
    page.get_by_role("button", name="Change node ID…").click()
    dialog = page.get_by_role("dialog")
    expect(dialog).to_contain_text("Set with PA-105 (2006:0A); node ids 1..127.")
    dialog.get_by_label("New node ID (1–127)").fill("1")
    dialog.get_by_role("button", name="Change node ID").click()
    expect(page).to_have_url(f"{server}/nodes/1/parameters", timeout=20_000)
    expect(page.get_by_text("Node 5 is now node 1")).to_be_visible()


def test_the_wizard_says_at_once_when_it_cannot(page: Page, server: str) -> None:
    page.goto(f"{server}/nodes/3/parameters")
    page.get_by_role("button", name="Change node ID…").click()
    dialog = page.get_by_role("dialog")
    expect(dialog.get_by_role("status")).to_contain_text("has no node-id parameter ServoDesk knows")
    expect(dialog.get_by_label("New node ID (1–127)")).to_have_count(0)
