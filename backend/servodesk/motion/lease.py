"""One controller per drive (DESIGN: Motion safety): the client that holds a node's control is
the only one whose motion commands pass; another must take over explicitly. Quick stop and
stopping a jog are open to everyone.

A client is named by `X-Client-Id` (REST) or the WebSocket `hello`. A request without one (a
script) is anonymous: it may command a node nobody holds, without taking it (its id would be
new on every request, so holding would only lock the script out of its next call), and is
refused where a named client holds the node.
"""

from __future__ import annotations

import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass

from servodesk.errors import ServodeskError
from servodesk.models.safety import ControllerHolder


@dataclass(frozen=True)
class Client:
    id: str
    name: str | None = None
    anonymous: bool = False

    @staticmethod
    def anonymous_one() -> Client:
        return Client(id=f"anonymous-{uuid.uuid4().hex[:8]}", anonymous=True)


class HeldByOtherError(ServodeskError):
    """A motion command from a client that does not hold the node's control."""

    def __init__(self, node: int, holder: ControllerHolder) -> None:
        self.node = node
        self.holder = holder
        who = holder.name or holder.client_id
        super().__init__(self.say("error.controlled_elsewhere", node=node, holder=who))


Changed = Callable[[int], None]  # node whose holder changed


class ControllerLease:
    def __init__(self, clock: Callable[[], float] = time.time) -> None:
        self._holders: dict[int, ControllerHolder] = {}
        self._clock = clock
        self._listeners: list[Changed] = []

    def add_listener(self, fn: Changed) -> None:
        self._listeners.append(fn)

    def holder(self, node: int) -> ControllerHolder | None:
        return self._holders.get(node)

    def held_by(self, client_id: str) -> list[int]:
        return [node for node, h in self._holders.items() if h.client_id == client_id]

    def nodes(self) -> list[int]:
        return list(self._holders)

    def holds(self, node: int, client: Client) -> bool:
        holder = self._holders.get(node)
        return holder is not None and holder.client_id == client.id

    def check(self, node: int, client: Client) -> bool:
        """May `client` command `node`? True when it should take the node first (free and the
        client is named); raises HeldByOtherError when someone else holds it."""
        holder = self._holders.get(node)
        if holder is None:
            return not client.anonymous
        if holder.client_id != client.id:
            raise HeldByOtherError(node, holder)
        return False

    def take(self, node: int, client: Client, *, take_over: bool) -> ControllerHolder | None:
        """Give `client` the node; returns the previous holder if it was someone else."""
        previous = self._holders.get(node)
        if previous is not None and previous.client_id != client.id and not take_over:
            raise HeldByOtherError(node, previous)
        if previous is not None and previous.client_id == client.id:
            return None
        self._holders[node] = ControllerHolder(
            client_id=client.id, name=client.name, since=self._clock()
        )
        self._changed(node)
        return previous

    def release(self, node: int) -> ControllerHolder | None:
        previous = self._holders.pop(node, None)
        if previous is not None:
            self._changed(node)
        return previous

    def _changed(self, node: int) -> None:
        for fn in list(self._listeners):
            fn(node)
