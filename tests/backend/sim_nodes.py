"""A real `NodeAccess` for service tests: simulated drives on a python-can virtual channel, a
canopen Network on a second bus instance of that channel, one RemoteNode and NodeSession per node.

Everything goes over CAN frames to the simulated drives, as with real hardware; only the node
registry is replaced by this small class.
"""

from __future__ import annotations

import asyncio
import uuid
from collections.abc import Sequence
from types import TracebackType

import can
import canopen
from canopen.objectdictionary import ObjectDictionary

import servodesk_data
from servodesk.errors import CommTimeoutError, NodeNotFoundError, SdoAbortError
from servodesk.models.network import NmtCommandName
from servodesk.models.nodes import NmtStateName, NodeInfo
from servodesk.nodes.session import NodeSession
from servodesk.od import ObjectDictionaryModel, load_od
from servodesk.od.to_canopen import to_canopen
from servodesk_data import DriveData
from servodesk_sim.frames import Frame
from servodesk_sim.runner import SimBus, run_drives

DEFAULT_DRIVES: tuple[tuple[int, str], ...] = ((1, "mdi-s1c"), (2, "kinco"), (3, "cia402"))
BOOT_UP = 0x700  # NMT error control (boot-up / heartbeat) base COB-ID
NOTIFIER_CYCLE = 0.02  # s

_NMT_CODES = {
    NmtCommandName.START: 0x01,
    NmtCommandName.STOP: 0x02,
    NmtCommandName.PRE_OPERATIONAL: 0x80,
    NmtCommandName.RESET_NODE: 0x81,
    NmtCommandName.RESET_COMMUNICATION: 0x82,
}


class SimNodes:
    """NodeAccess over simulated drives; close() (or `with`) shuts every bus down."""

    def __init__(
        self,
        drives: Sequence[tuple[int, str]] = DEFAULT_DRIVES,
        *,
        sdo_timeout: float = 0.5,
        bus_bitrate: int | None = None,
    ) -> None:
        self.channel = f"servodesk-test-{uuid.uuid4().hex}"
        self.sdo_timeout = sdo_timeout
        self.drive_bus = can.Bus(interface="virtual", channel=self.channel)
        self.sim: SimBus = run_drives(self.drive_bus, drives, bus_bitrate=bus_bitrate)
        self.network = canopen.Network()
        # the notifier's receive timeout: disconnect() waits for it, once per test
        self.network.NOTIFIER_CYCLE = NOTIFIER_CYCLE
        self.network.connect(interface="virtual", channel=self.channel)
        self.profiles: dict[int, str] = {}
        self._models: dict[int, ObjectDictionaryModel] = {}
        self._sessions: dict[int, NodeSession] = {}
        # the catalogue per profile; a test may replace one (an uploaded dictionary's mismatch)
        self.drive_data = {profile: servodesk_data.load(profile) for _, profile in drives}
        # nodes shown as generic (no catalogue), as the registry does for unknown identities
        self.generic_nodes: set[int] = set()
        for node, profile in drives:
            self._attach(node, profile)

    def __enter__(self) -> SimNodes:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def close(self) -> None:
        for session in self._sessions.values():
            session.close()
        self.network.disconnect()
        self.sim.stop()
        self.drive_bus.shutdown()

    def _attach(self, node: int, profile: str) -> None:
        model = load_od(servodesk_data.eds_path(profile), node_id=node)
        remote = canopen.RemoteNode(node, to_canopen(model, node))
        self.network.add_node(remote)
        self.profiles[node] = profile
        self._models[node] = model
        self._sessions[node] = NodeSession(remote, sdo_timeout=self.sdo_timeout)

    def set_od(self, node: int, model: ObjectDictionaryModel) -> None:
        """Use another dictionary for `node` (as after a user's EDS upload); the drive stays."""
        self._models[node] = model

    # ------------------------------------------------------------------------ NodeAccess

    def session(self, node: int) -> NodeSession:
        if node not in self._sessions:
            raise NodeNotFoundError(node)
        return self._sessions[node]

    def od(self, node: int) -> ObjectDictionaryModel:
        if node not in self._models:
            raise NodeNotFoundError(node)
        return self._models[node]

    def profile_data(self, node: int) -> DriveData | None:
        if node not in self.profiles:
            raise NodeNotFoundError(node)
        if node in self.generic_nodes:
            return None
        return self.drive_data[self.profiles[node]]

    def info(self, node: int) -> NodeInfo:
        if node not in self.profiles:
            raise NodeNotFoundError(node)
        profile = self.profiles[node]
        identity = self.drive_data[profile].identity
        return NodeInfo(
            node=node,
            # what the registry reads from 1018h/1000h at a scan
            vendor_id=identity.vendor_id,
            product_code=identity.product_code,
            device_type=identity.device_type,
            profile=profile,
            profile_label=identity.description,
            nmt_state=NmtStateName.UNKNOWN,
            online=True,
        )

    async def nmt(self, node: int, command: NmtCommandName) -> NodeInfo:
        code = _NMT_CODES[command]
        await self.session(node).run(
            lambda remote: remote.nmt.send_command(code), what=f"NMT {command.value}"
        )
        return self.info(node)

    async def wait_boot(self, node: int, timeout: float) -> bool:
        loop = asyncio.get_running_loop()
        seen = asyncio.Event()

        def on_frame(can_id: int, data: bytearray, timestamp: float) -> None:
            # notifier thread: hand over to the loop, no work here
            if data[:1] == b"\x00":
                loop.call_soon_threadsafe(seen.set)

        # subscribed before the first await (the NodeAccess contract)
        self.network.subscribe(BOOT_UP + node, on_frame)
        try:
            await asyncio.wait_for(seen.wait(), timeout)
        except TimeoutError:
            return False
        finally:
            self.network.unsubscribe(BOOT_UP + node, on_frame)
        return True

    async def answers(self, node: int) -> bool:
        """A 1000h read at `node` on the bus: its session's if listed, else a throw-away one."""
        if node in self._sessions:
            try:
                await self._sessions[node].upload(0x1000, 0)
            except CommTimeoutError:
                return False
            except SdoAbortError:
                return True
            return True
        remote = canopen.RemoteNode(node, ObjectDictionary())  # type: ignore[no-untyped-call]
        self.network.add_node(remote)
        probe = NodeSession(remote, sdo_timeout=self.sdo_timeout)
        try:
            await probe.upload(0x1000, 0)
        except CommTimeoutError:
            return False
        except SdoAbortError:
            return True
        finally:
            probe.close()
            del self.network[node]
        return True

    async def move(self, old: int, new: int) -> NodeInfo:
        profile = self.profiles.pop(old)
        self._models.pop(old)
        self._sessions.pop(old).close()
        del self.network[old]
        self._attach(new, profile)
        return self.info(new)


SDO_RX = 0x600  # SDO request COB-ID base
DOWNLOAD_COMMANDS = frozenset({0x21, 0x23, 0x27, 0x2B, 0x2F})  # SDO initiate download


class SdoTap:
    """SDO request frames that reached the simulated drives: to one node or to any, and only
    initiate downloads (writes) when `writes_only`. Proves what was (not) sent."""

    def __init__(self, nodes: SimNodes, node: int | None = None, *, writes_only: bool = False):
        self.node = node
        self.writes_only = writes_only
        self.frames: list[Frame] = []
        self.remove = nodes.sim.add_tap(self._on_frame)

    def _on_frame(self, frame: Frame, origin: object | None) -> None:
        target = frame.can_id - SDO_RX
        if not 1 <= target <= 0x7F or (self.node is not None and target != self.node):
            return
        if self.writes_only and frame.data[:1] not in {bytes([c]) for c in DOWNLOAD_COMMANDS}:
            return
        self.frames.append(frame)

    def commands(self) -> list[int]:
        """The command byte of each request seen, in order."""
        return [frame.data[0] for frame in self.frames]
