"""A data directory on a file system that is really full: a small tmpfs mounted for the test
(CI runs as root) and filled to its last byte, so SQLite gets ENOSPC from the kernel exactly as
on a full disk in the field."""

from __future__ import annotations

import contextlib
import errno
import os
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest

SIZE = "16m"  # room for the app's databases at start-up; then filled
CHUNK = 1 << 16


@contextlib.contextmanager
def small_filesystem(path: Path, *, read_only: bool = False) -> Iterator[Path]:
    """`path` as the mount point of a fresh tmpfs of SIZE (read-only if asked: a write fails
    with EROFS even for root); unmounted afterwards."""
    path.mkdir(parents=True, exist_ok=True)
    options = f"size={SIZE},mode=0700" + (",ro" if read_only else "")
    mount = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(path)],
        capture_output=True,
        text=True,
        check=False,
    )
    if mount.returncode != 0:
        pytest.skip(f"a full disk needs a tmpfs mount (root): {mount.stderr.strip()}")
    try:
        yield path
    finally:
        # lazy: the app's SQLite files may still be open in a thread that is shutting down
        subprocess.run(["umount", "-l", str(path)], check=False)


def fill(path: Path) -> None:
    """Write a filler file in `path` until the file system says it is full (ENOSPC)."""
    filler = path / "filler"
    block = b"\0" * CHUNK
    with open(filler, "ab", buffering=0) as out:
        for size in (CHUNK, 4096, 512, 1):
            try:
                while True:
                    out.write(block[:size])
            except OSError as error:
                if error.errno != errno.ENOSPC:
                    raise
    if os.statvfs(path).f_bavail != 0:
        raise AssertionError(f"{path} still has free blocks after filling")
