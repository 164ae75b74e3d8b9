"""A walk through Network, Drive, Faults and Scope with the browser set to 简体中文: every page
speaks Chinese, with no English words left in the interface. What stays as it is: what the
devices and the user named (the drive's 1008h name, its dictionary's object names and file,
the bus's channel), technical names a Chinese manual prints as they are (CANopen, NMT, SDO,
PDO, rpm, …) and the language switch's own "English". Screenshots of each page are kept in
build/screenshots/zh-*.png."""

from __future__ import annotations

import json
import re
import urllib.request
from collections.abc import Iterator

import pytest
from playwright.sync_api import Browser, Page

from tests.e2e.conftest import SCREENSHOTS

# words a Chinese page keeps as they are: names, units and the CANopen terms the manuals print
KEPT = {
    "CANopen",
    "ServoDesk",
    "Kinco",
    "Nanotec",
    "rerun",
    "rpm",
    "rev",
    "inc",
    "kbit",
    "Mbit",
    "English",  # the language switch offers English in English
    "Language",  # the switch's label reads "Language / 语言" in every language
}
# an English word: a letter and at least two lower-case letters (NMT, SDO, 60FDh, KiB, MDi
# and FAULT_IxIxT_BIT are names and codes, not words)
WORD = re.compile(r"(?<![\w./-])[A-Za-z][a-z]{2,}(?![\w/-])")


def api(url: str, path: str, body: object | None = None) -> object:
    data = None if body is None else json.dumps(body).encode()
    method = "GET" if body is None else "PUT"
    request = urllib.request.Request(
        url + path, data=data, method=method, headers={"content-type": "application/json"}
    )
    with urllib.request.urlopen(request, timeout=10) as answer:
        return json.loads(answer.read())


def device_words(url: str) -> list[str]:
    """What the devices themselves say, as the page shows it unchanged."""
    words: list[str] = []
    nodes = api(url, "/api/nodes")
    assert isinstance(nodes, list)
    for node in nodes:
        words += [node["name"] or "", node["od_filename"] or ""]
        drive = api(url, f"/api/nodes/{node['node']}/drive")
        assert isinstance(drive, dict)
        own = drive.get("drive_limits") or {}
        words += [own.get("velocity_source") or "", own.get("torque_source") or ""]
    health = api(url, "/api/health")
    assert isinstance(health, dict)
    words += [str(health["bus"]["channel"]), str(health["bus"]["interface"])]
    return sorted((w for w in words if w), key=len, reverse=True)


def english_left(page: Page, data: list[str]) -> list[str]:
    text = page.inner_text("body")
    for said in data:
        text = text.replace(said, " ")
    return sorted({w for w in WORD.findall(text) if w not in KEPT})


@pytest.fixture
def zh_page(browser: Browser) -> Iterator[Page]:
    context = browser.new_context(viewport={"width": 1366, "height": 900}, locale="zh-CN")
    tab = context.new_page()
    tab.set_default_timeout(15_000)
    try:
        yield tab
    finally:
        context.close()


def look(page: Page, name: str, data: list[str]) -> list[str]:
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(SCREENSHOTS / f"zh-{name}.png"), full_page=True)
    return english_left(page, data)


def test_network_drive_faults_and_scope_speak_chinese(server: str, zh_page: Page) -> None:
    page = zh_page
    page.goto(server + "/")
    page.locator("#nodes-heading").wait_for()
    page.get_by_text("总线已连接").first.wait_for()  # the timeline, by message id
    data = device_words(server)
    left = {"network": look(page, "network", data)}

    for node in (1, 2, 3):
        page.goto(f"{server}/nodes/{node}/drive")
        page.get_by_role("heading", name="状态机").wait_for()
        page.get_by_text("行程终点").wait_for()
        left[f"drive-{node}"] = look(page, f"drive-{node}", data)

    # a fault on each drive: MDi alarm 4, Kinco and CiA 402 0x2310 (simulator-only 5FF0h)
    for node, code in ((1, 4), (2, 0x2310), (3, 0x2310)):
        api(server, f"/api/nodes/{node}/sdo/5FF0/0", {"value": code})
    for node in (1, 2, 3):
        page.goto(f"{server}/nodes/{node}/faults")
        page.get_by_role("heading", name=re.compile("^故障中")).wait_for()
        page.get_by_text("原因：").first.wait_for()
        left[f"faults-{node}"] = look(page, f"faults-{node}", data)

    page.goto(f"{server}/nodes/1/drive")
    page.get_by_text("报警 4").first.wait_for()
    page.locator(".drive-fault", has_text="位置超差").wait_for()  # 603Fh read, in Chinese
    left["drive-1-fault"] = look(page, "drive-1-fault", data)

    page.goto(server + "/scope")
    page.get_by_role("heading", name="示波器").first.wait_for()
    left["scope"] = look(page, "scope", data)

    page.goto(server + "/")
    page.get_by_text("节点 2：").first.wait_for()  # the EMCY on the timeline, in Chinese
    left["network-after"] = look(page, "network-after", data)

    assert {name: words for name, words in left.items() if words} == {}
