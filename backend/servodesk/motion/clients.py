"""Client ids bound to who uses them (DESIGN: Motion safety).

A page or script names itself with a client id (`X-Client-Id`, the WebSocket's `hello`); the
controller lease, jog ownership and the page-closed and page-hidden triggers all go by it. Taken
as given, another login could say hello with an operator's id and then release the operator's
control (and its heartbeat protection) by closing its socket. So the first login (principal:
the acting user) to use an id holds it; another login's use of it is refused until the id is
idle again (no socket, no control held, no jog).
"""

from __future__ import annotations

from collections import OrderedDict

from servodesk.errors import ServodeskError

MAX_IDLE_IDS = 4096  # ids remembered though idle (a page that reloads gets a new one)


class ClientIdTakenError(ServodeskError):
    def __init__(self, client_id: str) -> None:
        self.client_id = client_id
        super().__init__(
            f"client id {client_id!r} is in use by another login: each page or script names "
            "itself with an id of its own"
        )


class ClientIds:
    def __init__(self) -> None:
        self._owner: OrderedDict[str, str] = OrderedDict()

    def claim(self, client_id: str, principal: str) -> None:
        """Bind `client_id` to `principal`, or raise ClientIdTakenError when another holds it."""
        owner = self._owner.get(client_id)
        if owner is not None and owner != principal:
            raise ClientIdTakenError(client_id)
        self._owner[client_id] = principal
        self._owner.move_to_end(client_id)
        while len(self._owner) > MAX_IDLE_IDS:
            self._owner.popitem(last=False)

    def forget(self, client_id: str) -> None:
        """The id is idle (its last socket closed, it holds nothing): anyone may use it."""
        self._owner.pop(client_id, None)
