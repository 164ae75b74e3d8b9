"""Access control and the audit log in Chromium against the simulated drives, served with
tokens: the app asks for a login, a wrong token says so, a viewer sees the drive's controls
off with the reason (quick stop on), an engineer's OD write shows up in the audit log with
old → new and who, and undoing it writes the old value back as an entry of its own."""

from __future__ import annotations

import re
import time
from collections.abc import Iterator

import pytest
from playwright.sync_api import Page, expect

from servodesk.app import STATIC_DIR
from tests.e2e.conftest import SCREENSHOTS
from tests.live_server import serve_simulated

# the server wants tokens of 12 characters or more
TOKENS = "engineer=eng-secret-1,operator=oper-secret-1,viewer=view-secret-1"


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    if not (STATIC_DIR / "index.html").is_file():
        pytest.fail("the frontend is not built: run `make frontend` (make test does it)")
    with serve_simulated(tmp_path_factory.mktemp("data"), overrides={"tokens": TOKENS}) as url:
        yield url


def shot(page: Page, name: str) -> None:
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SCREENSHOTS / name), full_page=True)


def log_in(page: Page, token: str) -> None:
    page.get_by_label("Access token").fill(token)
    page.get_by_role("button", name="Log in").click()


def od_value(page: Page, server: str, node: int, index: str) -> int:
    # page.request shares the browser's cookies: it is logged in as the page is
    response = page.request.get(f"{server}/api/nodes/{node}/sdo/{index}/0")
    assert response.ok, response.text()
    value = response.json()["value"]
    assert isinstance(value, int)
    return value


def test_roles_and_the_audit_log(page: Page, server: str) -> None:
    page.goto(f"{server}/nodes/1/drive")
    expect(page.get_by_role("heading", name="Log in")).to_be_visible()
    expect(page.get_by_label("Access token")).to_have_attribute("type", "password")
    assert page.request.get(f"{server}/api/nodes").status == 401

    log_in(page, "not-a-token")
    expect(page.get_by_role("alert")).to_contain_text("Wrong token")
    shot(page, "trust-login.png")

    # a viewer lands on the page they asked for, with the controls off and saying why
    log_in(page, "view-secret-1")
    expect(page).to_have_url(re.compile(r"/nodes/1/drive$"))
    expect(page.get_by_test_id("session-user")).to_have_text("viewer · viewer")
    enable = page.get_by_role("button", name="Enable", exact=True)
    expect(enable).to_be_disabled()
    expect(enable).to_have_attribute(
        "title", "Viewer role: read only — log in as an operator or engineer to enable the drive"
    )
    expect(page.get_by_role("button", name="Quick stop node 1")).to_be_enabled()
    expect(page.get_by_text("Live: connected")).to_be_visible()
    shot(page, "trust-drive-viewer.png")

    page.get_by_role("button", name="Log out").click()
    expect(page.get_by_label("Access token")).to_be_visible()
    assert page.request.get(f"{server}/api/session").status == 401

    # an engineer writes 6081h:00 profile velocity on the Object dictionary page
    log_in(page, "eng-secret-1")
    expect(page.get_by_test_id("session-user")).to_have_text("engineer · engineer")
    expect(page.get_by_text("Live: connected")).to_be_visible()
    before = od_value(page, server, 1, "6081")
    after = before + 111
    page.get_by_role("link", name="Object dictionary").first.click()
    page.get_by_label("Search objects").fill("6081")
    page.get_by_text("Profile velocity", exact=True).first.click()
    expect(page.get_by_role("heading", name="Profile velocity")).to_be_visible()
    page.get_by_label("New value").fill(str(after))
    page.get_by_role("button", name="Write", exact=True).click()
    deadline = time.monotonic() + 10
    while od_value(page, server, 1, "6081") != after:
        assert time.monotonic() < deadline, "the write did not reach the drive"
        time.sleep(0.1)

    page.get_by_role("link", name="Audit", exact=True).click()
    expect(page.get_by_role("heading", name="Audit log")).to_be_visible()
    write = page.get_by_role("row").filter(has_text="6081h:00").first
    expect(write).to_contain_text(f"{before} → {after}")
    expect(write).to_contain_text("engineer")
    expect(write).to_contain_text("OK")
    shot(page, "trust-audit.png")

    write.get_by_role("button", name=re.compile(r"^Undo entry \d+$")).click()
    dialog = page.get_by_role("dialog")
    expect(dialog).to_contain_text(f"Write {before} back to 6081h:00 on node 1, replacing {after}?")
    dialog.get_by_role("button", name=f"Write {before} back").click()
    expect(dialog).to_be_hidden()
    undo = page.get_by_role("row").filter(has_text=re.compile(r"undoes entry \d+")).first
    expect(undo).to_contain_text(f"{after} → {before}")
    expect(undo).to_contain_text("OK")
    expect(page.get_by_role("status").filter(has_text="Undo logged")).to_be_visible()
    assert od_value(page, server, 1, "6081") == before
    shot(page, "trust-audit-undone.png")
