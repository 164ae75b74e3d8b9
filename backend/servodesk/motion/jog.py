"""Hold-to-run jog (DESIGN: Motion safety): a jog moves only while keep-alives arrive.

Each jog has a timer on the event loop, re-armed by every keep-alive (REST or WebSocket); when
it fires, or when a stop trigger names the jog's node or owner (socket closed, page hidden, bus
error, heartbeat lost, EMCY), the axis is stopped through MotionService.stop, which goes through
the node session's priority lane. A stopped jog stays stopped: moving again needs a new jog.
"""

from __future__ import annotations

import asyncio
import logging
import uuid
from collections import OrderedDict
from collections.abc import Callable
from contextlib import AbstractAsyncContextManager, nullcontext
from dataclasses import dataclass, field
from typing import Literal, Protocol

from servodesk.errors import ServodeskError
from servodesk.motion.safety_models import JogInfo

log = logging.getLogger(__name__)

KEEP_STOPPED = 50  # stopped jogs remembered, so a late keep-alive learns why it stopped
KEEPALIVE_MISSED = "keep-alive missed"
REPLACED = "replaced by a new jog"  # ended without a stop: the new jog drives the axis


class JogNotFoundError(ServodeskError):
    def __init__(self, jog_id: str) -> None:
        self.jog_id = jog_id
        super().__init__(f"no jog {jog_id}")


class JogStoppedError(ServodeskError):
    """A keep-alive for a jog that was stopped: re-arming is explicit (start a new jog)."""

    def __init__(self, info: JogInfo) -> None:
        self.info = info
        super().__init__(
            f"jog {info.jog_id} on node {info.node} was stopped ({info.stop_reason}); "
            "start a new jog to move again"
        )


class Stopper(Protocol):
    async def stop(self, node: int, *, reason: str) -> None: ...


class ToolRecord(Protocol):
    """An audit entry around a write the tool makes by itself (AuditLog.by_tool)."""

    def __call__(
        self, action: str, node: int | None, what: str
    ) -> AbstractAsyncContextManager[object]: ...


@dataclass(frozen=True, slots=True)
class JogRamp:
    """How a jog ramps and what caps it, as MotionService.jog_start applied it."""

    acceleration_rpm_s: float | None = None  # pv
    torque_slope_pct_s: float | None = None  # pt
    velocity_limit_rpm: float | None = None  # pt
    velocity_limit_source: str | None = None  # pt: the object that caps the speed


@dataclass
class _Jog:
    info: JogInfo
    timer: asyncio.TimerHandle | None = None
    stopping: asyncio.Task[None] | None = field(default=None, repr=False)


Stopped = Callable[[JogInfo], None]


class JogWatchdog:
    def __init__(self, motion: Stopper, *, record: ToolRecord | None = None) -> None:
        self._motion = motion
        self._record = record
        self._jogs: OrderedDict[str, _Jog] = OrderedDict()
        self._listeners: list[Stopped] = []
        # nodes with a running jog, replaced (not mutated) so a notifier thread may read it
        self.running_nodes: frozenset[int] = frozenset()
        # nodes whose stop could not be sent (bus gone): sent again when the bus is back
        self.unsent: set[int] = set()

    def add_listener(self, fn: Stopped) -> None:
        """`fn(info)` when a jog stops, whatever the reason (the page shows why)."""
        self._listeners.append(fn)

    def register(
        self,
        node: int,
        mode: Literal["pv", "pt"],
        value: float,
        keepalive_ms: int,
        owner: str,
        *,
        ramp: JogRamp | None = None,
    ) -> JogInfo:
        """A jog whose axis was just started; its timer runs from now. Another running jog of
        the node is retired without stopping the axis (this one took it over)."""
        ramp = ramp or JogRamp()
        for jog in self._running():
            if jog.info.node == node:
                self._end(jog, REPLACED)
        info = JogInfo(
            jog_id=uuid.uuid4().hex,
            node=node,
            mode=mode,
            value=value,
            keepalive_ms=keepalive_ms,
            state="running",
            owner=owner,
            acceleration_rpm_s=ramp.acceleration_rpm_s,
            torque_slope_pct_s=ramp.torque_slope_pct_s,
            velocity_limit_rpm=ramp.velocity_limit_rpm,
            velocity_limit_source=ramp.velocity_limit_source,
        )
        jog = _Jog(info)
        self._jogs[info.jog_id] = jog
        self._arm(jog)
        self._nodes_changed()
        self._forget_old()
        return info

    def get(self, jog_id: str) -> JogInfo:
        return self._jog(jog_id).info

    def keepalive(self, jog_id: str) -> JogInfo:
        jog = self._jog(jog_id)
        if jog.info.state != "running":
            raise JogStoppedError(jog.info)
        self._arm(jog)
        return jog.info

    async def stop(self, jog_id: str, reason: str) -> JogInfo:
        """Stop one jog and wait until the stop was sent."""
        jog = self._jog(jog_id)
        self._stop(jog, reason)
        if jog.stopping is not None:
            await asyncio.wait({jog.stopping})
        return jog.info

    # `by_tool`: the tool stops the jog by itself (a trigger, not a user's request): the stop
    # gets its own audit entry by "servodesk"; a request's stop is in the request's entry.

    def stop_node(self, node: int, reason: str, *, by_tool: bool = False) -> list[JogInfo]:
        running = [jog for jog in self._running() if jog.info.node == node]
        return [self._stop(jog, reason, by_tool=by_tool) for jog in running]

    def stop_owner(self, owner: str, reason: str, *, by_tool: bool = False) -> list[JogInfo]:
        running = [jog for jog in self._running() if jog.info.owner == owner]
        return [self._stop(jog, reason, by_tool=by_tool) for jog in running]

    def stop_all(self, reason: str, *, by_tool: bool = False) -> list[JogInfo]:
        return [self._stop(jog, reason, by_tool=by_tool) for jog in self._running()]

    async def settled(self) -> None:
        """Wait until every stop in flight was sent (shutdown, tests)."""
        tasks = {j.stopping for j in self._jogs.values() if j.stopping is not None}
        if tasks:
            await asyncio.wait(tasks)

    def _running(self) -> list[_Jog]:
        return [jog for jog in self._jogs.values() if jog.info.state == "running"]

    def _jog(self, jog_id: str) -> _Jog:
        jog = self._jogs.get(jog_id)
        if jog is None:
            raise JogNotFoundError(jog_id)
        return jog

    def _arm(self, jog: _Jog) -> None:
        if jog.timer is not None:
            jog.timer.cancel()
        loop = asyncio.get_running_loop()
        jog.timer = loop.call_later(jog.info.keepalive_ms / 1000, self._expired, jog)

    def _expired(self, jog: _Jog) -> None:
        if jog.info.state == "running":
            self._stop(jog, f"{KEEPALIVE_MISSED} for {jog.info.keepalive_ms} ms", by_tool=True)

    def _end(self, jog: _Jog, reason: str) -> None:
        if jog.timer is not None:
            jog.timer.cancel()
            jog.timer = None
        jog.info = jog.info.model_copy(update={"state": "stopped", "stop_reason": reason})
        self._nodes_changed()
        for fn in list(self._listeners):
            fn(jog.info)

    def _stop(self, jog: _Jog, reason: str, *, by_tool: bool = False) -> JogInfo:
        if jog.info.state != "running":
            return jog.info
        self._end(jog, reason)
        jog.stopping = asyncio.get_running_loop().create_task(
            self._send_stop(jog.info.node, reason, by_tool), name=f"jog stop node {jog.info.node}"
        )
        return jog.info

    async def _send_stop(self, node: int, reason: str, by_tool: bool) -> None:
        entry: AbstractAsyncContextManager[object] = nullcontext()
        if by_tool and self._record is not None:
            entry = self._record("jog-stop", node, f"stop the jog of node {node}: {reason}")
        try:
            async with entry:
                await self._motion.stop(node, reason=reason)
            self.unsent.discard(node)
        except ServodeskError as error:
            self.unsent.add(node)
            # nothing more the tool can send; the drive's own heartbeat consumer is the backstop
            log.warning("node %d: stopping the jog (%s) failed: %s", node, reason, error)

    def _nodes_changed(self) -> None:
        self.running_nodes = frozenset(jog.info.node for jog in self._running())

    def _forget_old(self) -> None:
        stopped = [k for k, j in self._jogs.items() if j.info.state != "running"]
        for key in stopped[: max(0, len(stopped) - KEEP_STOPPED)]:
            del self._jogs[key]
