"""Drive values from the node's own TPDOs: the statusword, mode display, position, velocity,
torque, following error … as the frames carry them, so a reading needs no SDO for them.

The mapping comes from the PDO service's cache (what the device has, kept true on every
change), one subscription per valid TPDO. canopen calls the subscription on python-can's
notifier thread, which only keeps the frame and its arrival time (DESIGN rule 1); decoding
happens when a value is asked for.

A value counts only while it is current (`max_age`): a TPDO sent on SYNC every n periods or on
an event timer arrives again within its period, so an older frame means the drive stopped
sending it (NMT, a lost SYNC, a broken cable); one sent on change only (types 254/255 without a
timer) is current as long as the node is Operational — the drive sends it again whenever a
mapped value changes. Types 0 and 252/253 (acyclic, on request) are never taken as current.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import threading
import time
from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass

import canopen

from servodesk.errors import ServodeskError
from servodesk.od.model import ObjectDictionaryModel
from servodesk.pdo.decode import PdoDecoder
from servodesk.pdo.model import PdoConfig
from servodesk.pdo.service import PdoService
from servodesk_protocol.pdo import SYNC_CYCLIC_MAX

Clock = Callable[[], float]
Key = tuple[int, int]  # (index, sub-index)
EVENT_TYPES = (254, 255)  # sent on an event (a change, the event timer)
MARGIN_S = 0.02  # what a frame may be late by (inhibit time, bus, the notifier thread)
UNKNOWN_SYNC_S = 0.1  # the SYNC period assumed when another master produces SYNC
ASK_EVERY_S = 2.0  # an unknown mapping is read at most this often (a node that does not answer)
log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class Carried:
    """One object's value as a TPDO brought it."""

    value: int
    source: str  # "TPDO2"
    age_s: float


def max_age(pdo: PdoConfig, sync_period_s: float | None) -> float | None:
    """How old a frame of `pdo` may be and still show the drive now; None: any age (sent on
    change only); 0: never (sent on request or acyclic)."""
    kind = pdo.transmission_type
    if 1 <= kind <= SYNC_CYCLIC_MAX:
        period = sync_period_s if sync_period_s else UNKNOWN_SYNC_S
        return 2 * kind * period + MARGIN_S
    if kind in EVENT_TYPES:
        if pdo.event_timer_ms:
            return 1.5 * pdo.event_timer_ms / 1000 + MARGIN_S
        return None
    return 0.0


class _Tpdo:
    """One subscribed TPDO: the last frame (notifier thread) and how to read it (the loop)."""

    def __init__(self, pdo: PdoConfig, od: ObjectDictionaryModel, limit: float | None) -> None:
        self.label = f"TPDO{pdo.number}"
        self.cob_id = pdo.cob_id
        self.decoder = PdoDecoder(pdo.mapping, od)
        self.limit = limit
        self._lock = threading.Lock()
        self._data: bytes | None = None
        self._time = 0.0

    def record(self, data: bytes, now: float) -> None:
        with self._lock:
            self._data, self._time = data, now

    def read(self, now: float) -> tuple[list[int | float | bool], float] | None:
        """The last frame's values and age, when it is current and fits the mapping."""
        with self._lock:
            data, at = self._data, self._time
        if data is None or self.limit == 0.0 or len(data) < self.decoder.length:
            return None
        age = max(now - at, 0.0)
        if self.limit is not None and age > self.limit:
            return None
        return self.decoder.values(data), age


class NodeFeed:
    """The TPDOs of one node, subscribed on one canopen Network."""

    def __init__(
        self,
        network: canopen.Network,
        pdos: Sequence[PdoConfig],
        od: ObjectDictionaryModel,
        sync_period_s: float | None,
        clock: Clock = time.monotonic,
    ) -> None:
        self.network = network
        self.built_from = pdos  # the service's cached list: a new list means a new mapping
        self._clock = clock
        self._tpdos = [
            _Tpdo(pdo, od, max_age(pdo, sync_period_s))
            for pdo in pdos
            if pdo.kind == "tpdo" and pdo.valid and pdo.mapping
        ]
        self._callbacks: list[tuple[int, Callable[[int, bytearray, float], None]]] = []

    @property
    def carried(self) -> dict[Key, str]:
        """Every object a TPDO carries, with the TPDO's name (whether current or not)."""
        out: dict[Key, str] = {}
        for tpdo in self._tpdos:
            for field in tpdo.decoder.fields:
                out.setdefault((field.index, field.subindex), tpdo.label)
        return out

    def start(self) -> None:
        for tpdo in self._tpdos:
            callback = self._recorder(tpdo)
            self.network.subscribe(tpdo.cob_id, callback)
            self._callbacks.append((tpdo.cob_id, callback))

    def stop(self) -> None:
        for cob, callback in self._callbacks:
            with contextlib.suppress(ValueError):  # the network forgot it (a new connection)
                self.network.unsubscribe(cob, callback)
        self._callbacks.clear()

    def values(self, wanted: Collection[Key]) -> dict[Key, Carried]:
        """The current value of each wanted object a TPDO carries (typed by the dictionary)."""
        now = self._clock()
        out: dict[Key, Carried] = {}
        for tpdo in self._tpdos:
            read = None
            for position, field in enumerate(tpdo.decoder.fields):
                key = (field.index, field.subindex)
                if key not in wanted or key in out:
                    continue
                if read is None:
                    read = tpdo.read(now)
                    if read is None:
                        break
                value = read[0][position]
                if isinstance(value, float):  # a REAL mapped where an integer is meant
                    continue
                out[key] = Carried(int(value), tpdo.label, read[1])
        return out

    def _recorder(self, tpdo: _Tpdo) -> Callable[[int, bytearray, float], None]:
        clock = self._clock

        def on_frame(_can_id: int, data: bytearray, _timestamp: float) -> None:
            tpdo.record(bytes(data), clock())  # notifier thread: record only

        return on_frame


class TpdoFeeds:
    """The feeds of every node, kept in step with the PDO service's cache: a changed mapping
    (applied, read anew, forgotten after a raw write, a boot-up or NMT command) or a new bus
    connection builds the node's feed again."""

    def __init__(
        self,
        pdos: PdoService,
        *,
        operational: Callable[[int], bool],
        sync_period_s: Callable[[], float | None],
        clock: Clock = time.monotonic,
    ) -> None:
        self._pdos = pdos
        self._operational = operational
        self._sync_period_s = sync_period_s
        self._clock = clock
        self._feeds: dict[int, NodeFeed] = {}
        self._asked: dict[int, float] = {}  # node -> when its mapping was last asked for
        self._reads: set[asyncio.Task[object]] = set()

    def values(
        self, node: int, wanted: Collection[Key], *, ask: bool = False
    ) -> dict[Key, Carried]:
        """What the node's TPDOs carry of `wanted` now; empty outside Operational (the drive
        sends no PDOs there) or before its mapping is known. `ask`: then read the mapping in
        the background (the pages' polling does; a command's steps never wait behind it)."""
        if not self._operational(node):
            return {}
        feed = self._current(node, ask=ask)
        return feed.values(wanted) if feed is not None else {}

    def carried(self, node: int) -> dict[Key, str]:
        feed = self._current(node, ask=False)
        return feed.carried if feed is not None else {}

    def close(self) -> None:
        for feed in self._feeds.values():
            feed.stop()
        self._feeds.clear()
        for task in self._reads:
            task.cancel()

    def _current(self, node: int, *, ask: bool) -> NodeFeed | None:
        known = self._pdos.known(node)
        try:
            network: canopen.Network | None = self._pdos.network()
        except ServodeskError:  # no bus
            network = None
        feed = self._feeds.get(node)
        if feed is not None and (feed.built_from is not known or feed.network is not network):
            feed.stop()
            del self._feeds[node]
            feed = None
        if network is None:
            return None
        if known is None:
            if ask:
                self._ask(node)
            return None
        if feed is None:
            feed = NodeFeed(network, known, self._pdos.access.od(node), self._sync_period_s())
            feed.start()
            self._feeds[node] = feed
        return feed

    def _ask(self, node: int) -> None:
        """Read the node's PDOs once in the background (at most every ASK_EVERY_S): the next
        reading after it comes from the frames."""
        now = self._clock()
        if now - self._asked.get(node, -ASK_EVERY_S) < ASK_EVERY_S:
            return
        self._asked[node] = now
        try:
            task: asyncio.Task[object] = asyncio.get_running_loop().create_task(self._read(node))
        except RuntimeError:  # no loop (a blocking caller): the next one asks
            return
        self._reads.add(task)
        task.add_done_callback(self._reads.discard)

    async def _read(self, node: int) -> object:
        try:
            return await self._pdos.cached(node)
        except ServodeskError as error:  # offline, stopped, no bus: SDO readings say so
            log.debug("node %d: PDOs not read for the drive state: %s", node, error)
            return None
