"""What the SDO, parameter and parameter-set services need from the node registry.

The services depend on this Protocol, not on the registry class, so they can be tested against
any real implementation (the tests run one over simulated drives) and the registry stays free to
change how it keeps nodes.
"""

from __future__ import annotations

from typing import Protocol

from servodesk.models.network import NmtCommandName
from servodesk.models.nodes import NodeInfo
from servodesk.nodes.session import NodeSession
from servodesk.od import ObjectDictionaryModel
from servodesk_data import DriveData


class NodeAccess(Protocol):
    def session(self, node: int) -> NodeSession:
        """The node's serialized access path. NodeNotFoundError if the node is not known."""
        ...

    def od(self, node: int) -> ObjectDictionaryModel:
        """The node's object dictionary (the profile's EDS or the user's upload)."""
        ...

    def profile_data(self, node: int) -> DriveData | None:
        """The drive catalogue of the node's profile; None for generic nodes."""
        ...

    def info(self, node: int) -> NodeInfo:
        """What is known about the node. NodeNotFoundError if no such node is on the bus."""
        ...

    async def nmt(self, node: int, command: NmtCommandName) -> NodeInfo:
        """Send an NMT command to the node and return its updated state."""
        ...

    async def wait_boot(self, node: int, timeout: float) -> bool:
        """True once a boot-up frame (700h + node, data 00) arrives after the call started;
        False after `timeout` seconds without one.

        Implementations register their interest before their first suspension point, so that a
        caller can start `wait_boot` as a task, yield once, and only then trigger the reset: the
        boot-up of a fast drive is then never missed.
        """
        ...

    async def answers(self, node: int) -> bool:
        """Whether a device answers at `node` on the bus now (asked on the bus: a node the
        tool remembers may be gone, one it never listed may be there)."""
        ...

    async def move(self, old: int, new: int) -> NodeInfo:
        """The node formerly at `old` now answers at `new`: re-key it (session, dictionary)."""
        ...
