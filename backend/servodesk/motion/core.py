"""The motion service's shared core (DriveIo): the per-node axes and the drive I/O every part
of the service goes through: a step on the node's worker thread, a command object written in an
RPDO or by SDO (refused unsent when a stop went out after it was asked for), 6041h read, and what
the node's TPDOs carry now. The parts (drive_limits.py, readings.py, moves.py, home.py, ip.py,
state_machine.py) and MotionService itself each take it in their constructor."""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from typing import TypeVar

import canopen

from servodesk.motion import drive_io as io
from servodesk.motion.axis import Axis, units_of
from servodesk.motion.rated import default_limits
from servodesk.motion.units import DriveUnits
from servodesk.nodes.access import NodeAccess
from servodesk.nodes.session import StopCutInError
from servodesk.pdo.commands import RpdoRoutes
from servodesk.pdo.feed import TpdoFeeds
from servodesk.settings import Settings
from servodesk_protocol.cia402 import CONTROLWORD, MODES_OF_OPERATION, Cia402State, decode_state

T = TypeVar("T")
log = logging.getLogger(__name__)

# Command objects a reading holds: read by SDO, they are as known as what ServoDesk wrote (an
# RPDO that maps them beside a set-point can then be sent, pdo/commands.py)
READ_INTO_SENT = {"controlword": CONTROLWORD, "mode": MODES_OF_OPERATION}
STATE_OBJECTS = frozenset({CONTROLWORD, MODES_OF_OPERATION})  # a write changes what the drive shows
WRITTEN = "written"  # a value's source: what ServoDesk wrote and the drive confirmed


def state_of(statusword: int) -> Cia402State:
    try:
        return decode_state(statusword)
    except ValueError:
        return Cia402State.NOT_READY_TO_SWITCH_ON


class DriveIo:
    """The shared core: what every part of the motion service reads and writes through."""

    def __init__(
        self,
        registry: NodeAccess,
        settings: Settings,
        *,
        feeds: TpdoFeeds | None = None,
        routes: RpdoRoutes | None = None,
        on_statusword: Callable[[int, int], None] | None = None,
    ) -> None:
        self.registry = registry  # the nodes, their sessions and dictionaries (every part's)
        self.settings = settings
        self._axes: dict[int, Axis] = {}
        self._feeds = feeds  # the drive state from TPDOs (None: all by SDO)
        self._routes = routes  # commands in RPDOs (None: all by SDO)
        # (node, statusword) after every read of 6041h, on the event loop (the fault service
        # publishes CiA 402 state changes from it)
        self._on_statusword = on_statusword

    # ------------------------------------------------------------------ axes and units

    def axis(self, node: int) -> Axis:
        """What the service remembers about the node's axis (created at first use, with the
        drive's own limits from its dictionary)."""
        axis = self._axes.get(node)
        if axis is None:
            limits = default_limits(self.registry, self.settings, node, None)
            axis = Axis(node=node, limits=limits)
            self._axes[node] = axis
        return axis

    def units(self, node: int) -> DriveUnits:
        return units_of(self.axis(node).statics, self.registry.profile_data(node))

    # ------------------------------------------------------------------ node access

    async def run(
        self,
        node: int,
        fn: Callable[[canopen.RemoteNode], T],
        what: str,
        *,
        command: bool = True,
    ) -> T:
        """A step of a motion command or of a jog's watch: ahead of the node's queued reads
        (nodes/session.py). `command=False` for background reading (a page's poll, limits)."""
        return await self.registry.session(node).run(
            fn, what=f"{what} (node {node})", command=command
        )

    async def write(
        self, node: int, index: int, sub: int, value: int, kind: tuple[int, bool]
    ) -> None:
        """One command object to the drive: in the mapped RPDO where there is one whose other
        objects ServoDesk knows (pdo/commands.py), else by SDO. Refused unsent when a stop
        went to the drive after it was asked for (a queued write must not undo the stop)."""
        axis = self.axis(node)
        epoch = axis.stop_epoch
        asked_at = time.monotonic()
        frame = self._rpdo_frame(node, index, sub, value)
        axis.sent.pop(index, None)  # unknown until the drive has it

        def send(remote: canopen.RemoteNode) -> None:  # on the node's worker thread
            if axis.stop_epoch != epoch:
                raise StopCutInError
            if frame is None:
                io.write(remote, index, sub, value, kind)
            else:
                network, cob_id, data, _label = frame
                network.send_message(cob_id, data)

        route = f" in {frame[3]}" if frame is not None else ""
        await self.registry.session(node).run(
            send,
            what=f"write {index:04X}h:{sub:02X}h{route}",
            index=index,
            subindex=sub,
            command=True,
        )
        if sub == 0:
            axis.sent[index] = value
        if index in STATE_OBJECTS:
            axis.commanded(asked_at)  # what the drive shows now is read, not older frames

    def _rpdo_frame(
        self, node: int, index: int, sub: int, value: int
    ) -> tuple[canopen.Network, int, bytes, str] | None:
        """(network, COB-ID, payload, "RPDOn") when the command can go in an RPDO."""
        if self._routes is None or sub != 0:
            return None
        route = self._routes.route(node, index)
        network = self._routes.network() if route is not None else None
        if route is None or network is None:
            return None
        data = route.payload({**self.axis(node).sent, index: value})
        return (network, route.cob_id, data, route.label) if data is not None else None

    def forget_sent(self, node: int | None = None) -> None:
        """What ServoDesk wrote may no longer hold: another write, a reset, a stop."""
        axes = self._axes.values() if node is None else [self._axes.get(node)]
        for axis in axes:
            if axis is not None:  # a node never commanded has nothing to forget
                axis.sent.clear()

    async def controlword(self, node: int, word: int) -> None:
        await self.write(node, CONTROLWORD, 0, word, io.U16)

    async def statusword(self, node: int) -> int:
        statusword = await self.run(node, io.read_statusword, "read 6041h")
        self.axis(node).sdo_values["statusword"] = (statusword, time.monotonic())
        self.saw_statusword(node, statusword)
        return statusword

    def saw_statusword(self, node: int, statusword: int) -> None:
        if self._on_statusword is None:
            return
        try:
            self._on_statusword(node, statusword)
        except Exception:  # a listener's failure must never stop a motion command
            log.exception("node %d: statusword listener failed", node)

    def carried(
        self, node: int, *, ask: bool = False
    ) -> tuple[dict[str, int | None], dict[str, str]]:
        """The snapshot's objects the node's TPDOs carry now: (values, "TPDOn" by field);
        `ask`: read an unknown mapping in the background (TpdoFeeds.values)."""
        keys = {(index, 0): name for name, (index, _signed) in io.SNAPSHOT_OBJECTS.items()}
        carried = self._feeds.values(node, keys, ask=ask) if self._feeds is not None else {}
        values: dict[str, int | None] = {}
        sources: dict[str, str] = {}
        axis = self.axis(node)
        read = axis.sdo_values
        now = time.monotonic()
        for key, found in carried.items():
            name = keys[key]
            if now - found.age_s < axis.commanded_at:
                continue  # a frame from before the last command: read it by SDO
            newer = read.get(name)
            if newer is not None and newer[1] > now - found.age_s:
                # read after the frame came: the frame's change is still in its inhibit time
                values[name], sources[name] = newer[0], io.SDO
            else:
                values[name], sources[name] = found.value, found.source
        for name, index in READ_INTO_SENT.items():  # the controlword and mode ServoDesk wrote
            if name not in values and index in axis.sent:
                values[name], sources[name] = axis.sent[index], WRITTEN
        return values, sources
