"""When a synchronous PDO has its SYNC: one rule for validate, apply and a DCF load.

A PDO of transmission type 0–240 (or 252) acts only at SYNC. SYNC counts as present when
ServoDesk produces it or when another producer's SYNC was heard on the bus lately (the machine's
controller). Without either, a valid synchronous PDO is a warning, never a problem of the
mapping: on a bench the controller that produces SYNC in production is often not connected.
The warning stands until the user says where SYNC comes from (`sync_source: "external"`, the
machine's controller) or starts ServoDesk's producer. Pure: the service hands in what it knows.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

from servodesk.pdo.model import PdoConfig
from servodesk.pdo_problems import PdoKind, Problem, problem
from servodesk_protocol.pdo import SUB_TRANSMISSION, comm_index, is_synchronous, transmission_words

SyncSource = Literal["external"]  # SYNC comes from the machine's controller (PLC)
EXTERNAL: SyncSource = "external"


@dataclass(frozen=True)
class SyncPresence:
    """What is known about SYNC on the bus when a mapping is checked or written."""

    producing: bool  # ServoDesk's own producer runs
    heard: bool  # another producer's SYNC was heard on the bus lately
    source: SyncSource | None = None  # what the request says about SYNC

    @property
    def present(self) -> bool:
        return self.producing or self.heard

    @property
    def acknowledged(self) -> bool:
        return self.source == EXTERNAL


# what to do about a synchronous PDO without SYNC: the warning's message id (pdo_problems)
ASK = "pdo.sync_missing_ask"
LOADED = "pdo.sync_missing_loaded"


def sync_warnings(
    pdos: Sequence[PdoConfig], sync: SyncPresence, *, then: str = ASK
) -> list[Problem]:
    """One warning per valid synchronous PDO while nothing produces SYNC (empty otherwise);
    `then` (ASK, LOADED) says what to do about it."""
    if sync.present:
        return []
    out: list[Problem] = []
    seen: set[tuple[PdoKind, int]] = set()
    for pdo in pdos:
        key = (pdo.kind, pdo.number)
        if key in seen or not pdo.valid or not is_synchronous(pdo.transmission_type):
            continue
        seen.add(key)
        label = f"{pdo.kind.upper()}{pdo.number}"
        words = transmission_words(pdo.transmission_type, pdo.direction)
        comm = comm_index(pdo.direction, pdo.number) if pdo.number >= 1 else None
        # `t`: the page says the transmission type's words in its own language
        said: dict[str, str | int] = {"pdo": label, "words": words, "t": pdo.transmission_type}
        out.append(problem(pdo.kind, pdo.number, then, comm, SUB_TRANSMISSION, **said))
    return out


@dataclass(frozen=True)
class SyncCheck:
    """A mapping checked against the SYNC rule and everything else validate checks."""

    problems: list[Problem]  # refusals: the mapping itself is wrong for this node
    warnings: list[Problem]  # synchronous PDOs while nothing produces SYNC
    sync: SyncPresence

    @property
    def blocking(self) -> list[Problem]:
        """What stops a write: the problems, and the warnings nobody acknowledged."""
        return self.problems + ([] if self.sync.acknowledged else self.warnings)
