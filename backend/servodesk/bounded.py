"""What the audit log and the timeline keep of a value or a text: bounded, whatever a client
sent. A long one is kept shortened, with its full length noted, so a 100 MB string in a
request costs a few hundred bytes on disk, not 100 MB per row (docs/security.md)."""

from __future__ import annotations

import json
from typing import Any

VALUE_LIMIT = 200  # characters of a value (an SDO write's text, old → new)
TEXT_LIMIT = 1000  # characters of words (what was done, an error message)
DATA_LIMIT = 16 * 1024  # characters of an event's detail as JSON


def shorten(text: str, limit: int = VALUE_LIMIT) -> str:
    """`text`, or its first `limit` characters and how long it was."""
    if len(text) <= limit:
        return text
    return f"{text[:limit]}… ({len(text)} characters)"


def is_shortened(text: str, limit: int = VALUE_LIMIT) -> bool:
    return len(text) > limit


def bounded(data: Any, limit: int = TEXT_LIMIT) -> Any:
    """JSON-able `data` with every string in it shortened (keys too); other values as they
    are."""
    if isinstance(data, str):
        return shorten(data, limit)
    if isinstance(data, dict):
        return {shorten(str(k), limit): bounded(v, limit) for k, v in data.items()}
    if isinstance(data, list | tuple):
        return [bounded(item, limit) for item in data]
    return data


def bounded_json(data: dict[str, Any]) -> str:
    """An event's detail as stored: its strings shortened, and the whole at most DATA_LIMIT
    characters (a detail still too large is replaced by a note of its size)."""
    text = json.dumps(bounded(data), ensure_ascii=False, default=str)
    if len(text) <= DATA_LIMIT:
        return text
    return json.dumps({"truncated": f"{len(text)} characters of detail not stored"})
