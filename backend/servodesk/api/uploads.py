"""Uploaded files: read whole, up to a limit, or refuse in words (never cut one silently).

Browsers send a file part with a file name; scripts (`curl -F file=<set.dcf`) may send the
same content as a plain form field. Both are the file."""

from __future__ import annotations

from typing import Annotated

from fastapi import File, UploadFile
from starlette.datastructures import UploadFile as ReceivedFile  # what the form parser makes

from servodesk.errors import InvalidValueError

# Optional for the parser so an empty part is refused in words (an empty form field arrives as
# "missing"); every route that takes one says what is wrong through `read_limited`.
Upload = Annotated[
    UploadFile | str | None, File(description="the file (a file part or a form field)")
]


def upload_name(file: UploadFile | str | None, fallback: str) -> str:
    return (file.filename or fallback) if isinstance(file, ReceivedFile) else fallback


async def read_limited(
    file: UploadFile | str | None, limit: int, fallback: str = "the file"
) -> bytes:
    if file is None:
        raise InvalidValueError("no file given: send it as the multipart field 'file'")
    if isinstance(file, str):
        data = file.encode("utf-8")
    else:
        data = await file.read(limit + 1)
    if len(data) > limit:
        name = upload_name(file, fallback)
        raise InvalidValueError(f"{name}: larger than {limit // 1024} kB; nothing was read")
    return data
