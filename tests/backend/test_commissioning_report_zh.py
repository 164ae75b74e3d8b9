"""The hand-over report in Chinese (`lang=zh-CN`) through the API on the simulated MDi-S1-C:
the report's own words in Chinese, the data as stored, English unchanged by default; the
PDF read back with poppler's tools (Makefile system-deps installs them); and the words
module as a table: every message in both languages, the Commission page's step and status
words."""

from __future__ import annotations

import io
import json
import re
import string
import zipfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.commissioning import report, report_tables
from servodesk.commissioning.report_plot import capture_series, svg_plot
from servodesk.commissioning.report_words import EN, LANGS, MESSAGES, words_for
from servodesk.models.commissioning import STEP_KEYS, STEP_TITLES
from servodesk.models.scope import Capture, CaptureSignal
from servodesk.scope.samples import SAMPLES_SCHEMA
from servodesk.settings import Settings
from servodesk_protocol.pdo import Direction
from tests.backend.test_commissioning_report import ok, poppler

NODE = 1  # the simulated MDi-S1-C
REASON = "no home switch fitted on this axis"  # typed by the user: never translated
LOCALES = Path(__file__).resolve().parents[2] / "frontend" / "src" / "i18n" / "locales"
MADE = re.compile(r"\d{4}-\d\d-\d\d \d\d:\d\d:\d\d UTC\.</p>")  # the page's own date


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path_factory.mktemp("data"))
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


@pytest.fixture(scope="module")
def record(client: TestClient) -> dict[str, Any]:
    """A record with two steps run, one signed off, one skipped with a typed reason."""
    made = ok(client.post(f"/api/nodes/{NODE}/commissioning", json={"modes": ["pp"]}), 201)
    rid = made.json()["id"]
    for key in ("identity", "communication"):
        ok(client.post(f"/api/commissioning/{rid}/steps/{key}/run"))
    ok(client.put(f"/api/commissioning/{rid}/steps/pdo", json={"status": "done"}))
    body = {"status": "skipped", "reason": REASON}
    ok(client.put(f"/api/commissioning/{rid}/steps/homing", json=body))
    return dict(ok(client.get(f"/api/commissioning/{rid}")).json())


def _page(client: TestClient, rid: int, **params: str) -> str:
    return str(ok(client.get(f"/api/commissioning/{rid}/report", params=params)).text)


def test_zh_html_writes_chinese_and_keeps_the_data(
    client: TestClient, record: dict[str, Any]
) -> None:
    page = _page(client, record["id"], lang="zh-CN")
    assert '<html lang="zh-CN">' in page
    headings = ("调试报告：", "设备标识", "调试步骤", "PDO 映射", "调试期间的故障", "审计日志摘录")
    labels = ("设备名称（1008h）", "已完成", "待完成", "已跳过", "调试人", "验收人", "签名")
    for words in headings + labels:
        assert words in page, words
    # the step titles are the Commission page's, by key
    homing = page.split(f'id="step-{record["id"]}-homing"')[1].split("</h3>")[0]
    assert "回零" in homing
    assert "已跳过" in homing
    assert 'class="status status-skipped"' in homing  # the badge's colour in any language
    assert re.search(r"\d{4}年\d\d月\d\d日 \d\d:\d\d:\d\d UTC", page)  # dates
    assert '"第 " counter(page) " 页，共 " counter(pages) " 页"' in page  # the PDF's footer
    # the report's English words are gone...
    for english in ("Identity", "Commissioned by", "Faults during commissioning", ">done<"):
        assert english not in page, english
    # ...but what was typed or stored stays as it was
    assert REASON in page
    assert record["title"] in page
    assert record["identity"]["name"] in page


def test_default_is_english_as_before(client: TestClient, record: dict[str, Any]) -> None:
    default = _page(client, record["id"])
    assert '<html lang="en">' in default
    for words in ("Commissioning report: ", "Identity", "Steps", "Commissioned by", "to do"):
        assert words in default, words
    assert "Commissioning report made by ServoDesk on " in default
    assert '"page " counter(page) " of " counter(pages)' in default
    assert REASON in default
    assert not re.search(r"[\u4e00-\u9fff]", default)  # no Chinese words
    explicit = _page(client, record["id"], lang="en")
    assert MADE.sub("", explicit) == MADE.sub("", default)
    machine = ok(client.get("/api/commissioning/report", params={"lang": "zh-CN"})).text
    assert '<html lang="zh-CN">' in machine
    assert "调试报告：" in machine


def test_zh_pdf_holds_the_chinese_text_in_a_cjk_font(
    client: TestClient, record: dict[str, Any], tmp_path: Path
) -> None:
    response = ok(
        client.get(
            f"/api/commissioning/{record['id']}/report", params={"format": "pdf", "lang": "zh-CN"}
        )
    )
    assert response.content.startswith(b"%PDF")
    pdf = tmp_path / "report.pdf"
    pdf.write_bytes(response.content)
    text = "".join(poppler("pdftotext", str(pdf), "-").split())  # wrapped lines joined
    for words in ("设备标识", "调试步骤", "已完成", "回零", "调试人", "第1页，共"):
        assert words in text, words
    assert REASON.replace(" ", "") in text
    fonts = poppler("pdffonts", str(pdf))
    assert "WenQuanYi" in fonts, fonts


def test_zh_bundle_carries_the_chinese_report(client: TestClient, record: dict[str, Any]) -> None:
    response = ok(
        client.get(
            f"/api/commissioning/{record['id']}/report", params={"format": "zip", "lang": "zh-CN"}
        )
    )
    with zipfile.ZipFile(io.BytesIO(response.content)) as archive:
        assert {"report.pdf", "report.html", "record.json", "audit.csv"} <= set(archive.namelist())
        html = archive.read("report.html").decode()
        stored = json.loads(archive.read("record.json"))
    assert '<html lang="zh-CN">' in html
    assert "设备标识" in html
    assert stored["steps"][0]["title"] == "Identity"  # the record itself is not translated


@pytest.mark.parametrize("lang", ["fr", "zh", "ZH-CN", "en-US", ""])
def test_an_unknown_language_is_422(client: TestClient, record: dict[str, Any], lang: str) -> None:
    for path in (f"/api/commissioning/{record['id']}/report", "/api/commissioning/report"):
        response = client.get(path, params={"lang": lang})
        assert response.status_code == 422, (path, lang, response.text)


def _fields(text: str) -> set[str]:
    return {name for _, name, _, _ in string.Formatter().parse(text) if name}


def test_every_message_in_both_languages() -> None:
    assert LANGS == ("en", "zh-CN")
    english, chinese = MESSAGES["en"], MESSAGES["zh-CN"]
    assert set(english) == set(chinese)
    for message, text in english.items():
        assert text, message
        assert chinese[message], message
        assert _fields(text) == _fields(chinese[message]), message
    for message, text in english.items():  # English labels of keys are the titles made before
        if message.startswith("key."):
            assert text == report_tables._title(message.removeprefix("key.")), message
    assert {f"step.{key}" for key in STEP_KEYS} <= set(english)


def test_step_and_status_words_are_the_commission_pages() -> None:
    page = json.loads((LOCALES / "commission.zh-CN.json").read_text(encoding="utf-8"))
    common = json.loads((LOCALES / "zh-CN.json").read_text(encoding="utf-8"))
    zh = words_for("zh-CN")
    for key in STEP_KEYS:
        assert zh.step_title(key, STEP_TITLES[key]) == page["commission"]["stepTitle"][key]
        assert EN.step_title(key, STEP_TITLES[key]) == STEP_TITLES[key]
    step_words = common["status"]["step"]
    assert [zh.status(s) for s in ("to_do", "done", "failed", "skipped")] == [
        step_words["toDo"], step_words["done"], step_words["failed"], step_words["skipped"],
    ]  # fmt: skip
    assert zh.status("in_progress") == common["status"]["record"]["inProgress"]
    assert report.STATUS_WORDS == {
        "to_do": "to do", "done": "done", "failed": "failed", "skipped": "skipped",
    }  # fmt: skip


@pytest.mark.parametrize(
    ("kind", "direction", "english", "chinese"),
    [
        (0, Direction.TRANSMIT, "synchronous, acyclic", "同步非循环"),
        (1, Direction.TRANSMIT, "every SYNC", "每个 SYNC"),
        (5, Direction.TRANSMIT, "every 5th SYNC", "每 5 个 SYNC"),
        (255, Direction.RECEIVE, "applied on arrival", "收到即生效"),
        (254, Direction.TRANSMIT, "manufacturer-specific", "制造商自定义"),
        (200, Direction.RECEIVE, "synchronous", "同步"),
    ],
)
def test_transmission_words(kind: int, direction: Direction, english: str, chinese: str) -> None:
    assert english in EN.transmission(kind, direction)
    assert chinese in words_for("zh-CN").transmission(kind, direction)


def test_dates_and_cells_in_each_language() -> None:
    stamp = 1_795_780_000.25
    assert EN.when(stamp) == "2026-11-27 11:46:40 UTC"
    assert report_tables.when(stamp) == "2026-11-27 11:46:40 UTC"
    assert words_for("zh-CN").when(stamp) == "2026年11月27日 11:46:40 UTC"
    assert EN.when(None) == ""
    assert report_tables.cell("valid", True, words=words_for("zh-CN")) == "是"
    nested = {"node_id": 1, "read": {"605Ah": 2}}
    assert report_tables.cell("x", nested) == "Node id: 1; Read: (605Ah: 2)"
    zh = report_tables.cell("x", nested, words=words_for("zh-CN"))
    assert zh == "节点号: 1; 读取: (605Ah: 2)"


def test_plot_names_the_node_in_chinese(tmp_path: Path) -> None:
    time = np.linspace(0.0, 1.0, 50)
    table = pa.table(
        {"signal": np.zeros(50, dtype=np.int32), "time": time, "timestamp": time + 1.7e9,
         "raw": time, "value": time},
        schema=SAMPLES_SCHEMA,
    )  # fmt: skip
    samples = tmp_path / "samples.parquet"
    pq.write_table(table, samples)
    signal = CaptureSignal.model_construct(node=1, name="Velocity", unit="rpm")
    capture = Capture.model_construct(id=7, name="stop", signals=[signal])
    assert capture_series(capture, samples)[0].name == "Velocity (node 1)"
    series = capture_series(capture, samples, words=words_for("zh-CN"))
    assert series[0].name == "Velocity（节点 1）"  # the signal's name stays as captured
    assert "Velocity（节点 1） [rpm]" in svg_plot(series, "停机测试：采集 7")
