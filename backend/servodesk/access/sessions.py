"""Browser login sessions and the login rate limit.

The browser trades its token once for a random session id in an HttpOnly cookie: the token
never sits where page scripts can read it, and logging out ends the session on the server.
Sessions live in memory (a restart logs everyone out), bounded in number and age.
"""

from __future__ import annotations

import secrets
import time
from collections import OrderedDict, deque
from collections.abc import Callable
from dataclasses import dataclass

from servodesk.access.actor import Role

COOKIE = "servodesk_session"


@dataclass(frozen=True)
class LoginSession:
    user: str
    role: Role
    expires: float  # time.monotonic()


Ended = Callable[[], None]


class SessionStore:
    """Logins by session id. Each user holds at most `max_per_user` (a new login ends that
    user's oldest), and all users together `max_sessions` (the oldest login overall goes), so
    logging in again and again evicts only the guesser's own sessions. Whoever holds on to a
    session (a live WebSocket) can `watch` it and is told once when it ends: logged out,
    evicted or expired."""

    def __init__(
        self,
        *,
        max_age_s: float = 12 * 3600,
        max_sessions: int = 1000,
        max_per_user: int = 20,
    ) -> None:
        self.max_age_s = max_age_s
        self._max = max_sessions
        self._max_per_user = max_per_user
        self._sessions: OrderedDict[str, LoginSession] = OrderedDict()
        self._watchers: dict[str, list[Ended]] = {}

    def create(self, user: str, role: Role) -> str:
        self._prune()
        mine = [sid for sid, s in self._sessions.items() if s.user == user]  # oldest first
        for sid in mine[: max(0, len(mine) - self._max_per_user + 1)]:
            self._drop(sid)
        while len(self._sessions) >= self._max:
            self._drop(next(iter(self._sessions)))  # the oldest login goes first
        sid = secrets.token_urlsafe(32)
        self._sessions[sid] = LoginSession(user, role, time.monotonic() + self.max_age_s)
        return sid

    def get(self, sid: str) -> LoginSession | None:
        session = self._sessions.get(sid)
        if session is None:
            return None
        if session.expires < time.monotonic():
            self._drop(sid)
            return None
        return session

    def end(self, sid: str) -> None:
        self._drop(sid)

    def count(self, user: str) -> int:
        return sum(1 for s in self._sessions.values() if s.user == user)

    def watch(self, sid: str, ended: Ended) -> Ended | None:
        """Call `ended` once when the session ends (at its expiry at the latest, when the
        watcher asks `get` or a login prunes); returns the call that stops watching, or None
        when there is no such session (it has ended already)."""
        if self.get(sid) is None:
            return None
        self._watchers.setdefault(sid, []).append(ended)

        def unwatch() -> None:
            watchers = self._watchers.get(sid, [])
            if ended in watchers:
                watchers.remove(ended)
            if not watchers:
                self._watchers.pop(sid, None)

        return unwatch

    def _drop(self, sid: str) -> None:
        self._sessions.pop(sid, None)
        for ended in self._watchers.pop(sid, []):
            ended()

    def _prune(self) -> None:
        now = time.monotonic()
        for sid in [sid for sid, s in self._sessions.items() if s.expires < now]:
            self._drop(sid)


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
