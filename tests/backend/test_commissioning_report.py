"""The commissioning report (HTML, PDF) and bundle (zip) through the API on the simulated
MDi-S1-C: a record with identity, communication and limits run, a step signed off and a
parameter written; the PDF read back with poppler's tools (Makefile system-deps installs
them: these tests require them, they do not skip); the plot of a capture from synthetic
samples."""

from __future__ import annotations

import csv
import io
import json
import shutil
import subprocess
import zipfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from fastapi.testclient import TestClient
from markupsafe import Markup

from servodesk.access.actor import Role
from servodesk.access.policy import required_role
from servodesk.app import create_app
from servodesk.commissioning import report, report_tables
from servodesk.commissioning.report_plot import Series, capture_series, svg_plot
from servodesk.commissioning.report_tables import capture_ids
from servodesk.models.commissioning import STEP_KEYS
from servodesk.models.scope import Capture, CaptureSignal
from servodesk.scope.samples import SAMPLES_SCHEMA
from servodesk.settings import Settings

NODE = 1  # the simulated MDi-S1-C
PA_103 = "最大转速限制"  # PA-103's Chinese name in the MDi catalogue


def ok(response: Any, status: int = 200) -> Any:
    assert response.status_code == status, response.text
    return response


def poppler(tool: str, *args: str) -> str:
    path = shutil.which(tool)
    assert path is not None, f"{tool} is missing: `make system-deps` installs poppler-utils"
    done = subprocess.run([path, *args], capture_output=True, text=True, check=True, timeout=60)
    return done.stdout


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[TestClient]:
    settings = Settings(simulated=True, data_dir=tmp_path_factory.mktemp("data"))
    with TestClient(create_app(settings, static_dir=None)) as test_client:
        yield test_client


@pytest.fixture(scope="module")
def made(client: TestClient) -> dict[str, Any]:
    """A record with three steps run, one signed off and one parameter written (PA-103)."""
    record = ok(client.post(f"/api/nodes/{NODE}/commissioning", json={"modes": ["pp"]}), 201)
    rid = record.json()["id"]
    for key in ("identity", "communication", "limits"):
        ok(client.post(f"/api/commissioning/{rid}/steps/{key}/run"))
    ok(client.put(f"/api/commissioning/{rid}/steps/pdo", json={"status": "done"}))
    before = ok(client.get(f"/api/nodes/{NODE}/params/PA-103")).json()
    ok(client.put(f"/api/nodes/{NODE}/params/PA-103", json={"value": 4321}))
    ok(client.post(f"/api/commissioning/{rid}/steps/parameters/run"))
    entries = ok(client.get("/api/audit", params={"node": NODE})).json()
    write = next(e for e in entries if e["index"] == 0x2006 and e["subindex"] == 8)
    record = ok(client.get(f"/api/commissioning/{rid}")).json()
    return {"record": record, "old": before["value"], "audit_id": write["id"]}


def test_html_holds_identity_steps_and_the_change(client: TestClient, made: dict[str, Any]) -> None:
    record = made["record"]
    response = ok(
        client.get(f"/api/commissioning/{record['id']}/report", params={"format": "html"})
    )
    assert response.headers["content-type"].startswith("text/html")
    page = response.text
    identity = record["identity"]
    assert identity["name"] in page
    assert f"0x{identity['vendor_id']:08X}" in page
    assert f"0x{identity['product_code']:08X}" in page
    assert identity["software_version"] in page
    for step in record["steps"]:
        block = page.split(f'id="step-{record["id"]}-{step["key"]}"')[1].split("</h3>")[0]
        assert step["title"] in block
        assert step["status"].replace("_", " ") in block
    assert [s["status"] for s in record["steps"][:5]] == ["done"] * 5
    assert f"{made['old']} → 4321" in page
    assert f"#{made['audit_id']}" in page
    assert PA_103 in page  # the catalogue's label beside PA-103
    # self-contained: nothing fetched
    assert "<link" not in page
    assert "src=" not in page
    assert "Commissioned by" in page
    assert "Accepted by" in page
    assert "PDO mapping" in page
    assert "TPDO1" in page


def test_pdf_text_and_cjk_font(client: TestClient, made: dict[str, Any], tmp_path: Path) -> None:
    record = made["record"]
    response = ok(client.get(f"/api/commissioning/{record['id']}/report", params={"format": "pdf"}))
    assert response.headers["content-type"] == "application/pdf"
    assert response.content.startswith(b"%PDF")
    pdf = tmp_path / "report.pdf"
    pdf.write_bytes(response.content)
    text = poppler("pdftotext", "-layout", str(pdf), "-")
    assert record["identity"]["name"] in text
    assert f"0x{record['identity']['vendor_id']:08X}" in text
    assert "4321" in text
    # a narrow column may wrap the name: compare without the line breaks
    assert PA_103 in "".join(poppler("pdftotext", str(pdf), "-").split())
    fonts = poppler("pdffonts", str(pdf))
    assert "WenQuanYi" in fonts, fonts
    # a page to look at: pdftoppm -png -r 60 -f 1 -l 1
    poppler("pdftoppm", "-png", "-r", "60", "-f", "1", "-l", "1", str(pdf), str(tmp_path / "p"))
    assert list(tmp_path.glob("p*.png"))
    assert "Serif" not in fonts  # the page footer uses the report's fonts too


def test_bundle_members(client: TestClient, made: dict[str, Any]) -> None:
    record = made["record"]
    response = ok(client.get(f"/api/commissioning/{record['id']}/report", params={"format": "zip"}))
    assert response.headers["content-type"] == "application/zip"
    with zipfile.ZipFile(io.BytesIO(response.content)) as archive:
        names = set(archive.namelist())
        assert names == {
            "report.pdf", "report.html", "node1-mdi-s1c.dcf", "audit.csv", "record.json",
        }  # fmt: skip
        assert archive.read("report.pdf").startswith(b"%PDF")
        assert record["identity"]["name"] in archive.read("report.html").decode()
        assert json.loads(archive.read("record.json")) == record
        dcf = archive.read("node1-mdi-s1c.dcf").decode()
        assert "[DeviceInfo]" in dcf
        rows = list(csv.reader(io.StringIO(archive.read("audit.csv").decode("utf-8"))))
    assert rows[0][0] == "id"
    ids = [int(row[0]) for row in rows[1:]]
    assert made["audit_id"] in ids


def test_machine_report(client: TestClient, made: dict[str, Any]) -> None:
    other = ok(client.post("/api/nodes/2/commissioning", json={"modes": ["pp"]}), 201).json()
    page = ok(client.get("/api/commissioning/report", params={"nodes": "1,2"})).text
    assert f'id="record-{made["record"]["id"]}"' in page
    assert f'id="record-{other["id"]}"' in page
    by_id = ok(client.get("/api/commissioning/report", params={"ids": str(other["id"])})).text
    assert f'id="record-{other["id"]}"' in by_id
    assert f'id="record-{made["record"]["id"]}"' not in by_id
    pdf = ok(client.get("/api/commissioning/report", params={"format": "pdf", "nodes": "2"}))
    assert pdf.content.startswith(b"%PDF")


def test_errors_and_role(client: TestClient, made: dict[str, Any]) -> None:
    unknown = client.get("/api/commissioning/999999/report")
    assert unknown.status_code == 404
    assert unknown.json()["error"] == "commissioning_not_found"
    bad = client.get(f"/api/commissioning/{made['record']['id']}/report", params={"format": "doc"})
    assert bad.status_code == 422
    assert client.get("/api/commissioning/report", params={"format": "zip"}).status_code == 422
    assert client.get("/api/commissioning/report", params={"nodes": "1;2"}).status_code == 422
    absent = client.get("/api/commissioning/report", params={"nodes": "99"})
    assert absent.status_code == 404
    for path in ("/api/commissioning/1/report", "/api/commissioning/report"):
        assert required_role("GET", path) is Role.VIEWER


def _capture(signals: list[CaptureSignal]) -> Capture:
    # only the signals matter to the plot: the rest of a capture is left out
    return Capture.model_construct(id=7, name="stop", signals=signals)


def _signal(name: str, unit: str) -> CaptureSignal:
    return CaptureSignal.model_construct(node=1, name=name, unit=unit)


def test_plot_of_synthetic_samples(tmp_path: Path) -> None:
    time = np.linspace(-0.1, 0.5, 5000)
    velocity = np.where(time < 0, 1000.0, np.maximum(0.0, 1000.0 - 4000.0 * time))
    position = np.cumsum(velocity) * 1e-4
    count = len(time)
    table = pa.table(
        {
            "signal": np.concatenate([np.zeros(count), np.ones(count)]).astype(np.int32),
            "time": np.concatenate([time, time]),
            "timestamp": np.concatenate([time, time]) + 1.7e9,
            "raw": np.concatenate([velocity, position]),
            "value": np.concatenate([velocity, position]),
        },
        schema=SAMPLES_SCHEMA,
    )
    samples = tmp_path / "samples.parquet"
    pq.write_table(table, samples, row_group_size=1000)
    capture = _capture([_signal("Velocity <actual>", "rpm"), _signal("Position", "rev")])
    series = capture_series(capture, samples, buckets=100)
    assert [s.unit for s in series] == ["rpm", "rev"]
    assert len(series[0].time) <= 200
    assert float(series[0].value.max()) == 1000.0
    assert float(series[0].value.min()) == 0.0
    svg = svg_plot(series, "Stop test: capture 7")
    assert svg.startswith("<svg")
    assert svg.count("<polyline") == 2
    assert "Velocity &lt;actual&gt;" in svg  # names are escaped
    assert svg_plot([], "nothing") == ""
    # in the page: inline, not an image fetched from anywhere
    step = report.StepView(
        key="stop_test", title="Stop test", status="done", by="local", at="", reason="",
        tables=[], plots=[Markup(svg)],
    )  # fmt: skip
    flat = Series("flat", "", np.array([0.0, 1.0]), np.array([2.0, 2.0]))
    assert "<polyline" in svg_plot([flat], "flat")  # a constant signal still draws
    html = report.render_html([_axis(step)], title="t", generated=0.0)
    assert "<svg" in html
    assert "<polyline" in html


def _axis(step: report.StepView) -> report.AxisView:
    from servodesk.commissioning.report_tables import Table
    from servodesk.models.commissioning import CommissioningIdentity, CommissioningRecord

    identity = CommissioningIdentity(
        profile="mdi-s1c", profile_label="MDi", od_source="profile", od_filename="drive.eds"
    )
    record = CommissioningRecord(
        id=1, node=1, title="t", created=0.0, identity=identity, modes=[], steps=[],
        status="in_progress",
    )  # fmt: skip
    empty = Table("", [])
    return report.AxisView(record, "Node 1", "", [], [step], None, empty, empty)


def test_capture_ids_in_evidence() -> None:
    evidence = {"capture_id": 4, "runs": [{"capture": 5}, {"capture_ids": [4, 6]}], "x": True}
    assert capture_ids(evidence) == [4, 5, 6]
    assert STEP_KEYS[0] == "identity"


@pytest.mark.parametrize(
    ("key", "value", "text"),
    [
        ("sent_at", 1_795_780_000.25, "2026-11-27 11:46:40 UTC"),  # any …_at time stamp is a date
        ("stop_time_s", 0.1996, "0.1996"),  # a duration is not
        ("modes", ["pp", "pv"], "pp, pv"),
        ("missing", [], "—"),
        (
            "deceleration",
            {"object": "6085h", "rpm_s": 3000.0, "read": {"605Ah": 2}},
            "Object: 6085h; Rpm s: 3000; Read: (605Ah: 2)",
        ),
        ("vendor_id", 0x26C, "0x0000026C"),
    ],
)
def test_evidence_cells_read_as_words(key: str, value: Any, text: str) -> None:
    assert report_tables.cell(key, value).startswith(text)
