"""Audit log CSV cells made safe to open in a spreadsheet (OWASP "CSV Injection"): a cell that
starts with = + - @, a tab or a carriage return gets a leading single quote, so Excel or
LibreOffice shows it as text instead of running it as a formula (=HYPERLINK(…) from a request
body would otherwise be a live link in the auditor's sheet). Every cell is quoted by the csv
module, double quotes inside doubled.

Negative numbers are quoted too: a value -5 reads '-5. The export is for reading; a script
that needs the number strips one leading quote (docs/security.md)."""

from __future__ import annotations

import csv
import io
from collections.abc import Iterable

FORMULA_START = ("=", "+", "-", "@", "\t", "\r")


def safe_cell(value: object) -> str:
    text = "" if value is None else str(value)
    return f"'{text}" if text.startswith(FORMULA_START) else text


def csv_rows(rows: Iterable[Iterable[object]]) -> str:
    out = io.StringIO()
    writer = csv.writer(out, quoting=csv.QUOTE_ALL)
    for row in rows:
        writer.writerow([safe_cell(cell) for cell in row])
    return out.getvalue()
