"""One write of an entry as a single step on the node's thread: optionally the value before,
the download, optionally the value read back. Nothing from another request lands in between,
so an audit entry's old → new is what the drive really went through (docs/security.md)."""

from __future__ import annotations

from dataclasses import dataclass

import canopen
from canopen.sdo.exceptions import SdoAbortedError

from servodesk_protocol.sdo_abort import WRITE_ONLY


@dataclass
class WriteStep:
    """What the step saw. Filled on the node's thread as it goes, so a caller whose write
    failed still learns the value that was there before."""

    before: bytes | None = None  # None: not asked for, or the drive refused to read it
    after: bytes | None = None  # None: not asked for, or write-only


def write_step(
    remote: canopen.RemoteNode,
    index: int,
    subindex: int,
    data: bytes,
    *,
    read_first: bool,
    read_back: bool,
    seen: WriteStep,
) -> WriteStep:
    if read_first:
        try:
            seen.before = bytes(remote.sdo.upload(index, subindex))
        except SdoAbortedError:
            seen.before = None  # unreadable now: the write goes ahead, its old value unknown
    remote.sdo.download(index, subindex, data)
    if read_back:
        try:
            seen.after = bytes(remote.sdo.upload(index, subindex))
        except SdoAbortedError as abort:
            if int(abort.code) != WRITE_ONLY:
                raise
    return seen
