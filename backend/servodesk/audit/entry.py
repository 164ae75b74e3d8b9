"""An audit entry while its write runs, and what came of it. The running request's entry is a
context variable: the SDO write path fills in the object and the value it replaced, without
every service passing the entry along."""

from __future__ import annotations

import contextvars
from concurrent.futures import Future
from dataclasses import dataclass, field

from servodesk.access.actor import Actor

AuditValue = int | float | str | None

# Entries whose object and old value the SDO write path records (and which can be undone).
SINGLE_WRITES = frozenset({"sdo-write", "param", "undo"})


@dataclass(frozen=True)
class Outcome:
    result: str  # "ok" | "failed" | "unknown"
    abort_code: str | None = None  # "0x06010002"
    error: str | None = None  # the API's error code: "sdo_abort", "timeout" …
    message: str | None = None  # the abort code's meaning or the error in words

    @classmethod
    def ok(cls) -> Outcome:
        return cls("ok")

    @classmethod
    def of_error(cls, error: BaseException) -> Outcome:
        """An error in words, where no API names its kind (the app passes its own)."""
        code = getattr(error, "code_hex", None)
        return cls("failed", code if isinstance(code, str) else None, None, str(error))


@dataclass
class Pending:
    """An entry whose begin row is written (or queued, for stops) and whose result is not."""

    actor: Actor
    action: str
    node: int | None
    what: str
    index: int | None = None
    subindex: int | None = None
    old: AuditValue = None
    new: AuditValue = None
    undo_of: int | None = None
    detail: dict[str, object] = field(default_factory=dict)
    writes: int = 0  # single writes recorded so far
    # the entry's id, once its begin row is in the log (AuditLog.begin sets it)
    row: Future[int] = field(default_factory=Future)
    # what the write itself says came of it, where its answer is a success that describes a
    # failure (an IP stream that stalled answers 200 with the fault): it wins over "ok"
    verdict: Outcome | None = None

    def report(self, outcome: Outcome) -> None:
        self.verdict = outcome

    def records_object(self) -> bool:
        """The first write of a single-write entry names its object; later writes (a DCF load
        has hundreds) leave the entry as it is."""
        return self.action in SINGLE_WRITES and self.writes == 0

    def set_object(self, index: int, subindex: int, old: AuditValue) -> None:
        self.index, self.subindex, self.old = index, subindex, old
        self.writes += 1

    @property
    def undoable(self) -> bool:
        return (
            self.action in SINGLE_WRITES
            and self.writes == 1
            and self.index is not None
            and self.old is not None
        )


_ENTRY: contextvars.ContextVar[Pending | None] = contextvars.ContextVar(
    "servodesk_audit_entry", default=None
)


def current_entry() -> Pending | None:
    return _ENTRY.get()


def enter(entry: Pending) -> contextvars.Token[Pending | None]:
    return _ENTRY.set(entry)


def leave(token: contextvars.Token[Pending | None]) -> None:
    _ENTRY.reset(token)
