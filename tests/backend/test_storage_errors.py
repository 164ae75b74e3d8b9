"""A data directory that is read-only or full is said in one line: the server refuses to start
on one it cannot write, and a request that meets a full disk answers 507 storage_full instead
of an internal error (the audited writes answer 507 audit_unavailable first:
tests/backend/test_safety_disk_full.py)."""

from __future__ import annotations

import errno
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from servodesk.api.errors import storage_failure
from servodesk.app import create_app
from servodesk.cli import main
from servodesk.settings import Settings
from servodesk.storage.data_dir import data_dir_problem
from tests.backend.full_disk import fill, small_filesystem

LOG = b"(1.000000) can0 181#0102030405060708\n(1.001000) can0 701#05\n" * 50


def wrapped(inner: BaseException) -> BaseException:
    try:
        try:
            raise inner
        except OSError as error:
            raise RuntimeError("the store could not write") from error
    except RuntimeError as outer:
        return outer


@pytest.mark.parametrize(
    ("error", "expected"),
    [
        (OSError(errno.ENOSPC, "No space left on device"), (507, "storage_full")),
        (OSError(errno.EDQUOT, "Disk quota exceeded"), (507, "storage_full")),
        (wrapped(OSError(errno.ENOSPC, "No space left")), (507, "storage_full")),
        (OSError(errno.EROFS, "Read-only file system"), (503, "storage_read_only")),
        (OSError(errno.ENOENT, "No such file"), None),  # a bug of ours, not the disk
        (ValueError("x"), None),
    ],
)
def test_storage_failures_are_named(error: BaseException, expected: tuple[int, str] | None) -> None:
    found = storage_failure(error)
    assert (None if found is None else (found[0], found[1].error)) == expected


def test_the_server_does_not_start_on_a_read_only_data_directory(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    with small_filesystem(tmp_path / "ro", read_only=True) as read_only:
        data = read_only / "servodesk"
        monkeypatch.setenv("SERVODESK_DATA_DIR", str(data))
        assert main(["serve", "--sim", "--port", "1"]) == 2  # refused before it binds
        err = capsys.readouterr().err
        assert err == (
            f"servodesk: the data directory {data} cannot be written (Read-only file system): "
            "set SERVODESK_DATA_DIR to a directory ServoDesk may write\n"
        )
        assert data_dir_problem(tmp_path / "fine") is None


def test_a_full_disk_is_storage_full_not_an_internal_error(tmp_path: Path) -> None:
    with small_filesystem(tmp_path / "data") as data:
        settings = Settings(simulated=True, data_dir=data)
        app = create_app(settings, static_dir=None)
        with TestClient(app, raise_server_exceptions=False) as client:
            fill(data)
            refused = client.post("/api/logs/decode", files={"file": ("bus.log", LOG)})
            assert refused.status_code == 507, refused.text
            assert refused.json() == {
                "error": "storage_full",
                "message": "no space left on the disk of ServoDesk's data directory: free "
                "space there and try again (stops and disables still work)",
            }
