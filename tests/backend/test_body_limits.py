"""Request bodies over a route's limit are refused with 413 before they are parsed or stored
(api/body_limits.py, docs/limits.md): on the declared length before a byte is read, and for a
body without one (chunked) as soon as it passes the limit."""

from __future__ import annotations

import json
from collections.abc import AsyncIterator, Iterator
from pathlib import Path

import httpx
import pytest
from fastapi.testclient import TestClient

from servodesk.api.body_limits import (
    FILE_BODY_MAX,
    JSON_BODY_MAX,
    log_upload_limit,
    too_large_message,
)
from servodesk.app import create_app
from servodesk.settings import Settings

MIB = 1024 * 1024
SDO_ROUTE = "/api/nodes/3/sdo/6081/0"  # profile velocity, writable on the simulated drive
JSON_HEADERS = {"content-type": "application/json"}


def _padded(value: object, size: int) -> bytes:
    """Valid JSON of `size` bytes: parsed, it would be `value` (trailing blanks are allowed)."""
    text = json.dumps(value).encode()
    return text + b" " * (size - len(text))


def _chunks(data: bytes, size: int = 256 * 1024) -> Iterator[bytes]:
    for at in range(0, len(data), size):
        yield data[at : at + size]


def _assert_too_large(answer: httpx.Response, limit_text: str) -> None:
    assert answer.status_code == 413, answer.text
    body = answer.json()
    assert body["error"] == "too_large"
    assert f"larger than this route takes ({limit_text})" in body["message"]
    assert "nothing was read or stored" in body["message"]


def _velocity(client: TestClient) -> object:
    answer = client.get(SDO_ROUTE)
    assert answer.status_code == 200, answer.text
    return answer.json()["value"]


def test_an_oversized_sdo_write_is_refused_unwritten(client: TestClient) -> None:
    before = _velocity(client)
    body = _padded({"value": 1234}, JSON_BODY_MAX + 1)  # a write of 1234, were it read
    _assert_too_large(client.put(SDO_ROUTE, content=body, headers=JSON_HEADERS), "1 MiB")
    # without a declared length: refused once the limit is passed
    chunked = client.put(SDO_ROUTE, content=_chunks(body), headers=JSON_HEADERS)
    assert "content-length" not in chunked.request.headers
    _assert_too_large(chunked, "1 MiB")
    assert _velocity(client) == before
    # the attempt may be on record, as refused; never as a write
    audit = client.get("/api/audit").json()
    assert all((e["result"], e["error"]) == ("failed", "too_large") for e in audit)


def test_a_body_at_the_limit_is_read(client: TestClient) -> None:
    body = _padded({"value": 1234}, JSON_BODY_MAX)
    answer = client.put(SDO_ROUTE, content=body, headers=JSON_HEADERS)
    assert answer.status_code == 200, answer.text
    assert _velocity(client) == 1234


def test_an_oversized_pdo_set_is_refused_before_it_is_parsed(client: TestClient) -> None:
    pdos = client.get("/api/nodes/1/pdos").json()
    body = _padded({"pdos": pdos}, 3 * MIB)
    answer = client.post("/api/nodes/1/pdos/validate", content=body, headers=JSON_HEADERS)
    _assert_too_large(answer, "1 MiB")


def test_a_dictionary_upload_takes_its_file_limit(client: TestClient) -> None:
    files = {"file": ("big.eds", b"x" * (FILE_BODY_MAX + 1))}
    answer = client.post("/api/od/check", files=files)
    _assert_too_large(answer, "8.1 MiB")


def test_the_message_says_what_to_do() -> None:
    limit = log_upload_limit(Settings(log_upload_max_mb=256))
    message = too_large_message(limit)
    assert "logs up to 256 MiB are read" in message
    assert "SERVODESK_LOG_UPLOAD_MAX_MB" in message


class _Sender:
    """A request body that counts how much of it the server asked for."""

    def __init__(self, total: int, chunk: int = 256 * 1024) -> None:
        self.total = total
        self.chunk = chunk
        self.pulled = 0

    async def __aiter__(self) -> AsyncIterator[bytes]:
        head = (
            b'--b\r\nContent-Disposition: form-data; name="file"; filename="big.log"\r\n'
            b"Content-Type: application/octet-stream\r\n\r\n"
        )
        self.pulled += len(head)
        yield head
        line = b"(1700000000.000000) can0 181#0102030405060708\n"
        block = line * (self.chunk // len(line))
        while self.pulled < self.total:
            self.pulled += len(block)
            yield block
        yield b"\r\n--b--\r\n"


@pytest.fixture
def small_uploads(tmp_path: Path) -> Iterator[TestClient]:
    """The app with a 1 MiB log upload limit (the route then takes 9 MiB and a bit)."""
    settings = Settings(simulated=True, data_dir=tmp_path, log_upload_max_mb=1)
    with TestClient(create_app(settings, static_dir=None)) as client:
        yield client


def _upload(client: TestClient, sender: _Sender, *, declared: int | None) -> httpx.Response:
    """POST the log form through the app itself (ASGI): the body is pulled chunk by chunk as
    the server asks for it, so `sender.pulled` is what the server read."""

    async def send() -> httpx.Response:
        headers = {"content-type": "multipart/form-data; boundary=b"}
        if declared is not None:
            headers["content-length"] = str(declared)
        transport = httpx.ASGITransport(app=client.app)
        async with httpx.AsyncClient(transport=transport, base_url="http://testserver") as http:
            return await http.post("/api/logs/decode", content=sender, headers=headers)

    assert client.portal is not None
    return client.portal.call(send)


@pytest.mark.parametrize("declared", [True, False], ids=["content-length", "chunked"])
def test_an_oversized_log_upload_is_not_read_or_spooled(
    small_uploads: TestClient, tmp_path: Path, declared: bool
) -> None:
    limit = 9 * MIB + 64 * 1024
    sender = _Sender(total=40 * MIB)
    answer = _upload(small_uploads, sender, declared=40 * MIB if declared else None)
    _assert_too_large(answer, "9.1 MiB")
    assert "logs up to 1 MiB are read" in answer.json()["message"]
    if declared:
        assert sender.pulled == 0  # refused on the declared length: not a byte read
    else:
        assert sender.pulled <= limit + 2 * sender.chunk  # read up to the limit, then no more
    assert not list(tmp_path.glob("uploads/*"))
    assert not list(tmp_path.glob("logs/*"))
