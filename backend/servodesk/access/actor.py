"""Roles and the acting user of the running request (a context variable, so the one write path
can name who acts without every service passing it along)."""

from __future__ import annotations

import contextvars
import enum
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass


class Role(enum.IntEnum):
    """Ordered: each role may do what the ones below it may."""

    VIEWER = 1  # reads everything, may always stop
    OPERATOR = 2  # also enables, jogs, homes, resets faults, runs the scope
    ENGINEER = 3  # also writes parameters, OD, PDOs, DCF, store/restore, NMT, node id/bitrate

    @property
    def label(self) -> str:
        return self.name.lower()

    @classmethod
    def parse(cls, text: str) -> Role:
        try:
            return cls[text.strip().upper()]
        except KeyError:
            names = ", ".join(role.label for role in cls)
            raise ValueError(f"unknown role {text.strip()!r} (roles: {names})") from None


@dataclass(frozen=True)
class Actor:
    user: str
    role: Role
    client: str | None = None  # the client's address, "127.0.0.1:51234"

    def may(self, role: Role) -> bool:
        return self.role >= role


# Without tokens the tool serves loopback only, to whoever is at the machine.
LOCAL_USER = "local"
# What the server does by itself (a jog stopped because keep-alives stopped, shutdown).
SYSTEM = Actor("servodesk", Role.ENGINEER)

_ACTOR: contextvars.ContextVar[Actor] = contextvars.ContextVar("servodesk_actor", default=SYSTEM)


def current_actor() -> Actor:
    return _ACTOR.get()


@contextmanager
def acting(actor: Actor) -> Iterator[None]:
    token = _ACTOR.set(actor)
    try:
        yield
    finally:
        _ACTOR.reset(token)
