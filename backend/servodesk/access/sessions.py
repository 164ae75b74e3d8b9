"""Browser login sessions and the login rate limit.

The browser trades its token once for a random session id in an HttpOnly cookie: the token
never sits where page scripts can read it, and logging out ends the session on the server.
Sessions live in memory (a restart logs everyone out), bounded in number and age.
"""

from __future__ import annotations

import secrets
import time
from collections import OrderedDict, deque
from dataclasses import dataclass

from servodesk.access.actor import Role

COOKIE = "servodesk_session"


@dataclass(frozen=True)
class LoginSession:
    user: str
    role: Role
    expires: float  # time.monotonic()


class SessionStore:
    def __init__(self, *, max_age_s: float = 12 * 3600, max_sessions: int = 1000) -> None:
        self.max_age_s = max_age_s
        self._max = max_sessions
        self._sessions: OrderedDict[str, LoginSession] = OrderedDict()

    def create(self, user: str, role: Role) -> str:
        self._prune()
        while len(self._sessions) >= self._max:
            self._sessions.popitem(last=False)  # the oldest login goes first
        sid = secrets.token_urlsafe(32)
        self._sessions[sid] = LoginSession(user, role, time.monotonic() + self.max_age_s)
        return sid

    def get(self, sid: str) -> LoginSession | None:
        session = self._sessions.get(sid)
        if session is None:
            return None
        if session.expires < time.monotonic():
            del self._sessions[sid]
            return None
        return session

    def end(self, sid: str) -> None:
        self._sessions.pop(sid, None)

    def _prune(self) -> None:
        now = time.monotonic()
        for sid in [sid for sid, s in self._sessions.items() if s.expires < now]:
            del self._sessions[sid]


class LoginLimiter:
    """Failed logins and bearer tokens per client address in a sliding window, plus a cap over
    all addresses (guessing from many addresses at once) that holds back only addresses that
    failed too: one that has not failed is never locked out by others' guessing. Successes are
    not counted."""

    def __init__(
        self,
        *,
        per_client: int = 5,
        overall: int = 30,
        window_s: float = 60.0,
        max_clients: int = 10_000,
    ) -> None:
        self.per_client = per_client
        self.overall = overall
        self.window_s = window_s
        self._max_clients = max_clients
        self._failures: OrderedDict[str, deque[float]] = OrderedDict()
        self._all: deque[float] = deque()

    def retry_after(self, client: str, now: float | None = None) -> float:
        """Seconds until `client` may try again; 0 when it may now."""
        now = time.monotonic() if now is None else now
        self._expire(self._all, now)
        waits = [0.0]
        mine = self._failures.get(client)
        if mine is not None:
            self._expire(mine, now)
            if len(mine) >= self.per_client:
                waits.append(mine[0] + self.window_s - now)
            if mine and len(self._all) >= self.overall:
                waits.append(self._all[0] + self.window_s - now)
        return max(waits)

    def failed(self, client: str, now: float | None = None) -> None:
        now = time.monotonic() if now is None else now
        mine = self._failures.pop(client, None) or deque()
        mine.append(now)
        self._failures[client] = mine  # most recent last, so the oldest client goes first
        while len(self._failures) > self._max_clients:
            self._failures.popitem(last=False)
        self._all.append(now)

    def _expire(self, times: deque[float], now: float) -> None:
        while times and times[0] <= now - self.window_s:
            times.popleft()
