"""A step's evidence and figures as tables a technician reads (pure: the report template only
lays them out). Evidence is free-form JSON per step; lists of objects become tables, objects
become name/value rows, and numbers are printed the way the manuals print them: object
indices and identity codes in hex, times as UTC dates. The words (titles, column names, yes/no,
dates) come from `words` (report_words.py); evidence values stay as the record stored them."""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

from servodesk.commissioning.report_words import EN, Words

# evidence keys whose integers the manuals print in hex
HEX_KEYS = {"vendor_id": 8, "product_code": 8, "revision": 8, "serial": 8, "device_type": 8}
# objects whose value is a code, not a quantity: 1000h device type, 1018h identity, 605Ah
HEX_OBJECTS = {"1000:00", "1018:01", "1018:02", "1018:03", "1018:04"}
TIME_KEYS = {"at", "time", "created"}
# the unit a figure's name ends with ("stop_time_s", "overshoot_pct")
UNIT_SUFFIXES = {
    "_ms": "ms", "_s": "s", "_rpm": "rpm", "_pct": "%", "_percent": "%", "_rev": "rev",
    "_inc": "inc", "_counts": "inc", "_mm": "mm", "_deg": "°", "_hz": "Hz", "_a": "A",
}  # fmt: skip


@dataclass
class Table:
    title: str
    columns: list[str]
    rows: list[list[str]] = field(default_factory=list)


def when(stamp: float | None, words: Words = EN) -> str:
    return words.when(stamp)


def cell(key: str, value: Any, row: dict[str, Any] | None = None, words: Words = EN) -> str:
    """One value as text: hex where the manuals print hex, dates for time stamps (`at`,
    `created`, any `…_at`), lists and nested objects as words, never as JSON."""
    if value is None:
        return "—"
    if isinstance(value, bool):
        return words.yes_no(value)
    if isinstance(value, int | float) and _is_time(key, value):
        return words.when(float(value))
    if isinstance(value, int):
        if key == "index":
            return f"{value:04X}h"
        if key == "subindex":
            return f"{value:02X}h"
        if key in HEX_KEYS:
            return f"0x{value:0{HEX_KEYS[key]}X}"
        if key == "value" and row is not None and row.get("object") in HEX_OBJECTS:
            return f"0x{value:08X}"
        return str(value)
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, str):
        return value
    if isinstance(value, list | tuple):
        return ", ".join(cell(key, item, words=words) for item in value) or "—"
    if isinstance(value, dict):
        parts = [f"{_label(str(k), words)}: {_nested(str(k), v, words)}" for k, v in value.items()]
        return "; ".join(parts) or "—"
    return json.dumps(value, ensure_ascii=False, default=str)


def _nested(key: str, value: Any, words: Words) -> str:
    text = cell(key, value, words=words)
    return f"({text})" if isinstance(value, dict) and value else text


def _is_time(key: str, value: float) -> bool:
    """A UNIX time stamp: by its key, and large enough not to be a duration."""
    return (key in TIME_KEYS or key.endswith("_at")) and value > 1e9


def _title(key: str) -> str:
    """ "stop_time_s" → "Stop time s"; "605Ah" stays as the manuals write it."""
    words = key.replace("_", " ")
    return words[:1].upper() + words[1:]


def _label(key: str, words: Words) -> str:
    """An evidence key as the report names it: the words' label, else its English title."""
    return words.key_title(key) or _title(key)


def _is_rows(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def rows_table(title: str, items: list[dict[str, Any]], words: Words = EN) -> Table:
    columns: list[str] = []
    for item in items:
        columns.extend(k for k in item if k not in columns)
    return Table(
        title,
        [_label(c, words) for c in columns],
        [[cell(c, item.get(c), item, words) for c in columns] for item in items],
    )


def changes_table(
    entries: list[dict[str, Any]], labels: dict[str, str], words: Words = EN
) -> Table:
    """The parameters step: each write as old → new with the audit entry that proves it."""
    names = ("col.object", "col.name", "col.old_new", "col.audit_id", "col.by", "col.at")
    table = Table(words("table.changes"), [words(n) for n in names])
    for entry in entries:
        name = entry.get("name") or ""
        label = labels.get(str(entry.get("object")))
        old, new = (
            cell("old", entry.get("old"), words=words),
            cell("new", entry.get("new"), words=words),
        )
        table.rows.append(
            [
                f"{entry.get('index', 0):04X}h:{entry.get('subindex', 0):02X}",
                f"{name} — {label}" if label and label != name else name,
                f"{old} → {new}",
                f"#{entry.get('audit_id')}",
                str(entry.get("by") or ""),
                cell("at", entry.get("at"), words=words),
            ]
        )
    return table


def evidence_tables(
    key: str, evidence: dict[str, Any], labels: dict[str, str], words: Words = EN
) -> list[Table]:
    tables: list[Table] = []
    name_value = [words("col.name"), words("col.value")]
    plain = Table(words("table.evidence"), name_value)
    for name, value in evidence.items():
        if key == "parameters" and name == "entries" and isinstance(value, list):
            tables.append(changes_table(value, labels, words))
        elif _is_rows(value):
            tables.append(rows_table(_label(name, words), value, words))
        elif (
            isinstance(value, dict)
            and value
            and not any(isinstance(v, dict | list) for v in value.values())
        ):
            sub = Table(_label(name, words), list(name_value))
            sub.rows = [
                [words.row_name(str(k)), cell(str(k), v, words=words)] for k, v in value.items()
            ]
            tables.append(sub)
        elif value not in ([], {}):
            plain.rows.append([_label(name, words), cell(name, value, words=words)])
    return ([plain] if plain.rows else []) + tables


def figures_table(figures: dict[str, float], words: Words = EN) -> Table | None:
    if not figures:
        return None
    columns = [words("col.figure"), words("col.value"), words("col.unit")]
    table = Table(words("table.figures"), columns)
    for name, value in figures.items():
        unit = next((u for s, u in UNIT_SUFFIXES.items() if name.endswith(s)), "")
        shown = name[: -len(next(s for s in UNIT_SUFFIXES if name.endswith(s)))] if unit else name
        table.rows.append([_label(shown, words), f"{value:.6g}", unit])
    return table


def capture_ids(evidence: Any) -> list[int]:
    """Every capture id the evidence names (`capture_id`, `capture_ids`, or `capture` inside
    nested objects), each once, in the order found."""
    found: list[int] = []

    def visit(value: Any, key: str = "") -> None:
        if isinstance(value, dict):
            for k, v in value.items():
                visit(v, str(k))
        elif isinstance(value, list):
            for v in value:
                visit(v, key)
        elif (
            key in ("capture_id", "capture_ids", "capture", "captures")
            and isinstance(value, int)
            and not isinstance(value, bool)
            and value not in found
        ):
            found.append(value)

    visit(evidence)
    return found
