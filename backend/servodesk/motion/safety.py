"""The safety layer over MotionService (DESIGN: Motion safety): who controls each drive (lease),
the drive's own stop if the tool dies (heartbeat consumer), hold-to-run jogs and every trigger
that stops them: keep-alive missed, socket closed, page hidden, bus error, heartbeat lost, EMCY.

Callbacks from python-can's notifier thread only hand the frame to the loop
(`call_soon_threadsafe`); everything else runs on the event loop, which must never block (the
jog timers live there).
"""

from __future__ import annotations

import asyncio
import logging
import uuid
from collections import Counter
from collections.abc import Coroutine
from contextlib import AbstractAsyncContextManager, nullcontext
from typing import Any

from servodesk.access.actor import current_actor
from servodesk.bus.connection import BusManager
from servodesk.errors import InvalidValueError, ServodeskError
from servodesk.events.bus import BusEvent, EventKind
from servodesk.models.bus import BusState, BusStatus
from servodesk.models.motion import DriveCommand, DriveState
from servodesk.models.safety import ControllerInfo, JogInfo, JogRequest, QuickStopResult
from servodesk.motion.clients import ClientIds
from servodesk.motion.heartbeat import HeartbeatGuard
from servodesk.motion.jog import JogWatchdog, ToolRecord
from servodesk.motion.lease import Client, ControllerLease
from servodesk.motion.service import MotionService
from servodesk.motion.stop_reasons import Reason
from servodesk.nodes.registry import NodeRegistry
from servodesk.settings import Settings
from servodesk_protocol.emcy import ERROR_RESET

log = logging.getLogger(__name__)

POWER_DOWN = frozenset({"shutdown", "disable_operation", "disable_voltage"})
# the first two bytes of an EMCY "error reset / no error" (code 0000h): not a reason to stop
_RESET_BYTES = ERROR_RESET.to_bytes(2, "little")


class MotionSafety:
    def __init__(
        self,
        motion: MotionService,
        bus: BusManager,
        registry: NodeRegistry,
        settings: Settings,
        *,
        record: ToolRecord | None = None,
    ) -> None:
        self.motion = motion
        self.lease = ControllerLease()
        # what the tool writes by itself (stops on a trigger, 1016h after a reboot) is audited
        self._record = record
        self.jogs = JogWatchdog(motion, settings, record=record)
        self.jogs.add_listener(self._on_jog_changed)
        self.clients = ClientIds()
        # nodes held for a script's jog (no X-Client-Id): node -> (its client id, principal);
        # released once the jog's axis is at rest
        self._script_leases: dict[int, tuple[str, str]] = {}
        self._pt_speed_cap = settings.jog_pt_speed_cap_rpm
        self.heartbeat = HeartbeatGuard(
            registry,
            settings,
            network=lambda: bus.network,
            known_nodes=lambda: [info.node for info in registry.all()],
        )
        self._registry = registry
        self._max_keepalive = settings.jog_keepalive_max_ms
        self._sockets: Counter[str] = Counter()
        self._tasks: set[asyncio.Task[None]] = set()
        self.loop: asyncio.AbstractEventLoop | None = None
        self._unsubscribe = [
            bus.add_listener(self._on_bus),
            registry.events.subscribe(self._on_event),
            # ahead of the fault service's hand-over: the stop must not wait behind decoding
            bus.frames.on_emcy(self._emcy_heard, first=True),
        ]

    def start(self) -> None:
        self.loop = asyncio.get_running_loop()

    async def close(self) -> None:
        for unsubscribe in self._unsubscribe:
            unsubscribe()
        why = Reason("stop.shutting_down")
        self.jogs.stop_all(why, by_tool=True)
        await self.jogs.settled()
        for node in self.lease.nodes():
            self.lease.release(node)
        for node in self.heartbeat.guarded():  # 1016h back as it was, each write audited
            async with self._recorded(True, "release", node, f"release node {node}: {why}"):
                await self.heartbeat.unprotect(node)
        await self.heartbeat.close()

    # ------------------------------------------------------------------ control (lease)

    def controller(self, node: int, client: Client) -> ControllerInfo:
        self._registry.info(node)  # NodeNotFoundError for an unknown node
        return ControllerInfo(
            node=node,
            holder=self.lease.holder(node),
            you=self.lease.holds(node, client),
            protection=self.heartbeat.status(node),
        )

    def claim(self, client: Client) -> None:
        """The client id belongs to the acting login (motion/clients.py); ClientIdTakenError
        when another login uses it."""
        if not client.anonymous:
            self.clients.claim(client.id, current_actor().user)

    async def authorize(self, node: int, client: Client) -> None:
        """Let `client`'s motion command through, or raise HeldByOtherError. A named client
        commanding a node nobody holds takes it; a script (no client id) passes where its own
        jog holds the node."""
        self._registry.info(node)
        self.claim(client)
        if client.anonymous and self._script_holder(node) is not None:
            return
        if self.lease.check(node, client):
            await self.take(node, client, take_over=False)

    def _script_holder(self, node: int) -> str | None:
        """The client id of the acting login's script jog that holds `node`, if any."""
        held = self._script_leases.get(node)
        holder = self.lease.holder(node)
        if held is None or holder is None or holder.client_id != held[0]:
            return None
        return held[0] if held[1] == current_actor().user else None

    async def take(self, node: int, client: Client, *, take_over: bool) -> ControllerInfo:
        self._registry.info(node)
        if client.anonymous:
            raise InvalidValueError("taking control needs a client id (X-Client-Id header)")
        self.claim(client)
        previous = self.lease.take(node, client, take_over=take_over)
        if previous is not None:
            who = client.name or client.id
            self.jogs.stop_node(node, Reason("stop.taken_over", holder=who))
        await self.heartbeat.protect(node)
        return self.controller(node, client)

    async def release(self, node: int, client: Client) -> ControllerInfo:
        self._registry.info(node)
        self.claim(client)
        if self.lease.holder(node) is not None:
            self.lease.check(node, client)  # only the holder releases
            await self._release(node, Reason("stop.released"))
        return self.controller(node, client)

    async def _release(self, node: int, reason: str, *, by_tool: bool = False) -> None:
        self.jogs.stop_node(node, reason, by_tool=by_tool)
        self.lease.release(node)
        entry = self._recorded(by_tool, "release", node, f"release node {node}: {reason}")
        async with entry:
            await self.heartbeat.unprotect(node)

    def _recorded(
        self, by_tool: bool, action: str, node: int, what: str
    ) -> AbstractAsyncContextManager[object]:
        if by_tool and self._record is not None:
            return self._record(action, node, what)
        return nullcontext()

    # ------------------------------------------------------------------ jogs and stops

    async def start_jog(self, node: int, request: JogRequest, client: Client) -> JogInfo:
        pv = request.mode == "pv"
        value = request.velocity_rpm if pv else request.torque_pct
        other = request.torque_pct if pv else request.velocity_rpm
        unit = "velocity_rpm" if pv else "torque_pct"
        if value is None or other is not None:
            raise InvalidValueError(f"a {request.mode} jog takes {unit} (and only that)")
        if pv and request.torque_slope_pct_s is not None:
            raise InvalidValueError(
                "torque_slope_pct_s is for pt jogs; a pv jog takes an acceleration_rpm_s"
            )
        if not pv and request.acceleration_rpm_s is not None:
            raise InvalidValueError(
                "acceleration_rpm_s is for pv jogs; a pt jog takes a torque_slope_pct_s"
            )
        if request.keepalive_ms > self._max_keepalive:
            raise InvalidValueError(f"keepalive_ms above {self._max_keepalive}")
        cap = self._speed_cap(node, request)
        owner = await self._jog_owner(node, client)
        await self.motion.jog_start(
            node,
            request.mode,
            value,
            acceleration_rpm_s=request.acceleration_rpm_s,
            torque_slope_pct_s=request.torque_slope_pct_s,
        )
        ramp = self.motion.jog_ramp(
            node, request.mode, request.acceleration_rpm_s, request.torque_slope_pct_s
        )
        return self.jogs.register(
            node,
            request.mode,
            value,
            request.keepalive_ms,
            owner.id,
            principal=current_actor().user,
            ramp=ramp,
            speed_cap_rpm=cap,
        )

    def _speed_cap(self, node: int, request: JogRequest) -> float | None:
        """A torque jog's own speed cap: the request's, else the settings', never above the
        speed limit in force."""
        if request.mode != "pt":
            if request.speed_cap_rpm is not None:
                raise InvalidValueError("speed_cap_rpm is for pt jogs; a pv jog has its speed")
            return None
        limit = self.motion.limits(node).max_velocity_rpm
        cap = request.speed_cap_rpm or min(self._pt_speed_cap, limit)
        if cap > limit:
            raise InvalidValueError(
                f"speed_cap_rpm {cap:g} is above the speed limit in force, {limit:g} rpm"
            )
        return cap

    async def _jog_owner(self, node: int, client: Client) -> Client:
        """Who owns the jog, with the lease and the drive-side heartbeat protection taken for
        it. A script without a client id gets an id of its own for this node, held until its
        jog's axis is at rest: a jog is never without the drive's own stop if ServoDesk dies."""
        if not client.anonymous:
            await self.authorize(node, client)
            return client
        self._registry.info(node)
        held = self._script_holder(node)
        if held is not None:
            holder = self.lease.holder(node)
            return Client(id=held, name=holder.name if holder else None)
        user = current_actor().user
        script = Client(id=f"script-{uuid.uuid4().hex[:8]}", name=f"script ({user})")
        self.lease.check(node, client)  # HeldByOtherError where a page holds it
        self.clients.claim(script.id, user)
        self._script_leases[node] = (script.id, user)
        await self.take(node, script, take_over=False)
        return script

    def _on_jog_changed(self, jog: JogInfo) -> None:
        """A script's lease ends when its jog's axis is at rest (and no other jog runs)."""
        if jog.state != "stopped":
            return
        held = self._script_leases.get(jog.node)
        if held is None or held[0] != jog.owner or jog.node in self.jogs.moving_nodes():
            return
        holder = self.lease.holder(jog.node)
        del self._script_leases[jog.node]
        self.clients.forget(held[0])
        if holder is not None and holder.client_id == held[0]:
            self._spawn(self._release(jog.node, "the script's jog ended", by_tool=True))

    def keepalive(self, jog_id: str, client: Client) -> JogInfo:
        """A keep-alive counts only from the jog's owner (same login; same client id where
        one is named)."""
        return self.jogs.keepalive(
            jog_id,
            client_id=None if client.anonymous else client.id,
            principal=current_actor().user,
        )

    async def command(self, node: int, command: DriveCommand, client: Client) -> DriveState:
        """One controlword command (POST …/drive/command): quick stop is open to everyone, the
        rest pass the lease; a command that powers the drive down ends its jogs first."""
        if command == "quick_stop":
            return await self.quick_stop(node)
        await self.authorize(node, client)
        if command in POWER_DOWN:
            self.jogs.stop_node(
                node, Reason("stop.drive_command", drive_command=command.replace("_", " "))
            )
        return await self.motion.command(node, command)

    async def quick_stop(self, node: int) -> DriveState:
        """Open to every client, whoever holds the node."""
        self.jogs.stop_node(node, Reason("stop.quick_stop"))
        return await self.motion.quick_stop(node)

    async def quick_stop_all(self) -> QuickStopResult:
        nodes = [info.node for info in self._registry.all()]
        # the quick stops' tasks first: each reaches its node's priority lane ahead of the
        # jog's own stop (a halt that reads the drive first, then finds nothing to halt)
        stops = asyncio.gather(
            *(self.motion.quick_stop(node) for node in nodes), return_exceptions=True
        )
        self.jogs.stop_all(Reason("stop.quick_stop_all"))
        outcomes = await stops
        stopped: list[int] = []
        failed: dict[str, str] = {}
        for node, outcome in zip(nodes, outcomes, strict=True):
            if isinstance(outcome, ServodeskError):
                failed[str(node)] = str(outcome)
            elif isinstance(outcome, BaseException):
                raise outcome
            else:
                stopped.append(node)
        return QuickStopResult(stopped=stopped, failed=failed)

    # ------------------------------------------------------------------ triggers

    def socket_opened(self, client_id: str) -> None:
        self._sockets[client_id] += 1

    def socket_closed(self, client_id: str) -> None:
        """A page's socket closed: its jogs stop; the last socket of a client releases the
        drives it holds (nobody is left to keep them, and the drive must not fault later)."""
        self.jogs.stop_owner(client_id, Reason("stop.page_closed"), by_tool=True)
        self._sockets[client_id] -= 1
        if self._sockets[client_id] <= 0:
            del self._sockets[client_id]
            for node in self.lease.held_by(client_id):
                self._spawn(self._release(node, "the controlling page closed", by_tool=True))

    def page_hidden(self, client_id: str) -> list[JogInfo]:
        return self.jogs.stop_owner(client_id, Reason("stop.page_hidden"), by_tool=True)

    def socket_idle(self, client_id: str) -> None:
        """After socket_closed: an id with no socket, no control and no jog is free again."""
        if (
            client_id not in self._sockets
            and not self.lease.held_by(client_id)
            and not self.jogs.running_of(client_id)
        ):
            self.clients.forget(client_id)

    def _emcy_heard(self, node: int, data: bytes) -> None:
        """Notifier thread (the bus's frame tap): an EMCY from a node with a running jog goes
        straight to the loop; an "error reset" EMCY is no reason to stop."""
        loop = self.loop
        if loop is None or node not in self.jogs.running_nodes or data[:2] == _RESET_BYTES:
            return
        loop.call_soon_threadsafe(self.on_emcy, node, data)

    def on_emcy(self, node: int, data: bytes) -> None:
        code = int.from_bytes(data[:2], "little")
        self.jogs.stop_node(node, Reason("stop.emcy", code=f"{code:04X}"), by_tool=True)

    def _on_bus(self, status: BusStatus) -> None:
        if status.state is not BusState.CONNECTED:
            state = status.state.value
            why = (
                Reason("stop.bus_error", bus_state=state, error=status.error)
                if status.error
                else Reason("stop.bus", bus_state=state)
            )
            self.jogs.stop_all(why, by_tool=True)
            return
        for node in list(self.jogs.unsent):  # the bus is back: send what could not be sent
            self._spawn(self._stop_again(node))

    async def _stop_again(self, node: int) -> None:
        reason = "stop sent again after the bus came back"
        try:
            async with self._recorded(True, "jog-stop", node, f"stop node {node}: {reason}"):
                await self.motion.stop(node, reason=reason)
            self.jogs.unsent.discard(node)
        except ServodeskError as error:
            log.warning("node %d: stop after reconnect failed: %s", node, error)

    def _on_event(self, event: BusEvent) -> None:
        if event.node is None:
            return
        if event.kind is EventKind.NODE_LOST:
            self.jogs.stop_node(event.node, Reason("stop.heartbeat_lost"), by_tool=True)
        elif event.kind is EventKind.BOOT_UP:
            self.jogs.stop_node(event.node, Reason("stop.restarted"), by_tool=True)
            if self.lease.holder(event.node) is not None:
                # a reset reloads 1016h: set it again for the holder
                self._spawn(self._reprotect(event.node))

    async def _reprotect(self, node: int) -> None:
        self.heartbeat.forget(node)
        what = f"protect node {node} again after its restart (heartbeat consumer 1016h)"
        async with self._recorded(True, "heartbeat", node, what):
            await self.heartbeat.protect(node)

    def _spawn(self, coro: Coroutine[Any, Any, None]) -> None:
        task = asyncio.get_running_loop().create_task(coro)
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)
