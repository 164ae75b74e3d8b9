"""Uploaded files: read whole, up to a limit, or refuse in words (never cut one silently)."""

from __future__ import annotations

from fastapi import UploadFile

from servodesk.errors import InvalidValueError


async def read_limited(file: UploadFile, limit: int) -> bytes:
    data = await file.read(limit + 1)
    if len(data) > limit:
        name = file.filename or "the file"
        raise InvalidValueError(f"{name}: larger than {limit // 1024} kB; nothing was read")
    return data
