"""Routes that take no body refuse one with fields, as body models refuse unknown fields
(models/base.py, RequestBody): `POST /api/quick-stop {"value": …}` is an error, not a stop with a
comment that lands in the audit log. No body, an empty one, `{}` and `null` are accepted."""

from __future__ import annotations

import json
from typing import Any

from fastapi import Request
from fastapi.exceptions import RequestValidationError

TAKES_NO_BODY = "this request takes no body: send none (or {})"


def problems(body: bytes) -> list[dict[str, Any]]:
    """Why `body` is refused, as FastAPI's validation errors; empty when it is none at all."""
    if not body.strip():
        return []
    try:
        parsed = json.loads(body)
    except ValueError:
        parsed = ...  # not JSON: a body all the same
    if parsed is None or parsed == {}:
        return []
    if isinstance(parsed, dict):
        return [
            {"loc": ("body", str(name)[:100]), "msg": f"unknown field; {TAKES_NO_BODY}",
             "type": "extra_forbidden"}
            for name in list(parsed)[:20]
        ]  # fmt: skip
    return [{"loc": ("body",), "msg": TAKES_NO_BODY, "type": "extra_forbidden"}]


async def refuse_body(request: Request) -> None:
    found = problems(await request.body())
    if found:
        raise RequestValidationError(found)
