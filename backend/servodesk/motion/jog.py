"""Hold-to-run jog (DESIGN: Motion safety): a jog moves only while keep-alives arrive.

Each jog has a timer on the event loop, re-armed by every keep-alive from its owner (REST or
WebSocket); when it fires, or when a stop trigger names the jog's node or owner (socket closed,
page hidden, bus error, heartbeat lost, EMCY, a torque jog passing its speed cap), the axis is
stopped through MotionService.stop on the node session's priority lane, with a deceleration
ServoDesk bounds (never only the client's ramp). The jog is then "stopping" until the watchdog
has read the axis at rest — a torque jog that coasts or a drive that ignores the halt gets a
quick stop after the time its deceleration should have taken — and only then "stopped". A
stopped jog stays stopped: moving again needs a new jog.
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
from servodesk.models.safety import JogInfo
from servodesk.motion.stop_reasons import Params, Reason, nested_stop, said, then
from servodesk.settings import Settings

log = logging.getLogger(__name__)

KEEP_STOPPED = 50  # stopped jogs remembered, so a late keep-alive learns why it stopped
REPLACED = Reason("stop.replaced")  # ended without a stop: the new jog drives the axis
REST_READINGS = 2  # consecutive readings below jog_rest_rpm: at rest
STOP_MARGIN = 1.5  # × the time the deceleration should take, before a quick stop follows
STOP_SLACK = 0.5  # s added to that (the first readings, a drive's own ramp start)
WATCH_AFTER_QUICK_STOP = 10.0  # s: how long a quick-stopped axis is watched before giving up
# A keep-alive timer that fires this late found the loop busy past the deadline: keep-alives
# the page sent in time may wait unread in its socket (read a turn or two of the loop later).
LATE_S = 0.05
LISTEN_S = 0.05  # then the loop listens this long before the jog is stopped (once per deadline)


class JogNotFoundError(ServodeskError):
    def __init__(self, jog_id: str) -> None:
        self.jog_id = jog_id
        super().__init__(f"no jog {jog_id}")


class NotJogOwnerError(ServodeskError):
    """A keep-alive from someone other than the jog's owner: it must not keep the axis moving."""

    def __init__(self, info: JogInfo) -> None:
        self.info = info
        super().__init__(
            f"jog {info.jog_id} on node {info.node} belongs to another client: only the page "
            "or script that started it keeps it moving (anyone may stop it)"
        )


class JogStoppedError(ServodeskError):
    """A keep-alive for a jog that was stopped: re-arming is explicit (start a new jog)."""

    def __init__(self, info: JogInfo) -> None:
        self.info = info
        super().__init__(
            self.say(
                "error.jog_stopped",
                jog_id=info.jog_id,
                node=info.node,
                **nested_stop(info.stop_reason, info.stop_reason_id, info.stop_reason_params),
            )
        )


class Stopper(Protocol):
    async def stop(
        self,
        node: int,
        *,
        reason: str,
        quick: bool = False,
        deceleration_rpm_s: float | None = None,
        drive_deceleration: bool = False,
    ) -> str: ...

    async def velocity_rpm(self, node: int) -> float: ...

    async def reading(self, node: int) -> tuple[float, float]: ...  # rpm, rev

    def travel(self, node: int) -> tuple[float | None, float | None]: ...  # rev


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
    principal: str  # who started it (the login's user): only they keep it alive
    timer: asyncio.TimerHandle | None = None
    deadline: float = 0.0  # loop time by which the next keep-alive is due
    sent: asyncio.Event = field(default_factory=asyncio.Event, repr=False)
    stopping: asyncio.Task[None] | None = field(default=None, repr=False)
    watch: asyncio.Task[None] | None = field(default=None, repr=False)
    reason: str = ""  # why it stopped: the Reason itself (JogInfo keeps its words and id)


Changed = Callable[[JogInfo], None]


class JogWatchdog:
    def __init__(
        self, motion: Stopper, settings: Settings, *, record: ToolRecord | None = None
    ) -> None:
        self._motion = motion
        self._record = record
        self._floor = settings.jog_stop_deceleration_rpm_s
        self._rest = settings.jog_rest_rpm
        self._interval = settings.jog_watch_interval
        self._jogs: OrderedDict[str, _Jog] = OrderedDict()
        self._listeners: list[Changed] = []
        # nodes with a running jog, replaced (not mutated) so a notifier thread may read it
        self.running_nodes: frozenset[int] = frozenset()
        # nodes whose stop could not be sent (bus gone): sent again when the bus is back
        self.unsent: set[int] = set()

    def add_listener(self, fn: Changed) -> None:
        """`fn(info)` when a jog ends ("stopping", whatever the reason: the page shows why) and
        again when its axis is at rest ("stopped")."""
        self._listeners.append(fn)

    def register(
        self,
        node: int,
        mode: Literal["pv", "pt"],
        value: float,
        keepalive_ms: int,
        owner: str,
        *,
        principal: str,
        ramp: JogRamp | None = None,
        speed_cap_rpm: float | None = None,
    ) -> JogInfo:
        """A jog whose axis was just started; its timer runs from now. Another running jog of
        the node is retired without stopping the axis (this one took it over)."""
        ramp = ramp or JogRamp()
        for jog in list(self._jogs.values()):
            if jog.info.node != node or jog.info.state == "stopped":
                continue
            if jog.info.state == "running":
                self._retire(jog)
            elif jog.stopping is not None and jog.sent.is_set():
                # still watching the last jog slow down: the new one drives the axis now
                jog.stopping.cancel()
                self._update(
                    jog,
                    state="stopped",
                    stop_reason=then(jog.reason, "stop.then_replaced"),
                )
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
            speed_cap_rpm=speed_cap_rpm if mode == "pt" else None,
            stop_deceleration_rpm_s=max(ramp.acceleration_rpm_s or 0.0, self._floor),
        )
        jog = _Jog(info, principal=principal)
        self._jogs[info.jog_id] = jog
        self._arm(jog)
        if info.speed_cap_rpm is not None or self._motion.travel(node) != (None, None):
            jog.watch = asyncio.get_running_loop().create_task(
                self._watch_running(jog), name=f"jog watch node {node}"
            )
        self._nodes_changed()
        self._forget_old()
        return info

    def get(self, jog_id: str) -> JogInfo:
        return self._jog(jog_id).info

    def keepalive(self, jog_id: str, *, client_id: str | None, principal: str) -> JogInfo:
        """Re-arm the jog's timer. Only its owner counts: the same login, and the same client
        id where the keep-alive names one (a script that sent none may keep its own jog)."""
        jog = self._jog(jog_id)
        if principal != jog.principal or (client_id is not None and client_id != jog.info.owner):
            raise NotJogOwnerError(jog.info)
        if jog.info.state != "running":
            raise JogStoppedError(jog.info)
        self._arm(jog)
        return jog.info

    async def stop(self, jog_id: str, reason: str) -> JogInfo:
        """Stop one jog and wait until the stop was sent (not until the axis is at rest: the
        answer says "stopping" while it decelerates)."""
        jog = self._jog(jog_id)
        self._stop(jog, reason)
        if jog.stopping is not None:
            await jog.sent.wait()
        return jog.info

    # `by_tool`: the tool stops the jog by itself (a trigger, not a user's request): the stop
    # gets its own audit entry by "servodesk" and brakes at least on the drive's quick stop
    # deceleration; a request's stop is in the request's entry.

    def stop_node(self, node: int, reason: str, *, by_tool: bool = False) -> list[JogInfo]:
        running = [jog for jog in self._running() if jog.info.node == node]
        return [self._stop(jog, reason, by_tool=by_tool) for jog in running]

    def stop_owner(self, owner: str, reason: str, *, by_tool: bool = False) -> list[JogInfo]:
        running = [jog for jog in self._running() if jog.info.owner == owner]
        return [self._stop(jog, reason, by_tool=by_tool) for jog in running]

    def stop_all(self, reason: str, *, by_tool: bool = False) -> list[JogInfo]:
        return [self._stop(jog, reason, by_tool=by_tool) for jog in self._running()]

    def running_of(self, owner: str) -> list[JogInfo]:
        return [jog.info for jog in self._running() if jog.info.owner == owner]

    def moving_nodes(self) -> set[int]:
        """Nodes whose jog is running or still stopping."""
        return {j.info.node for j in self._jogs.values() if j.info.state != "stopped"}

    async def settled(self) -> None:
        """Wait until every stop in flight was sent (tests)."""
        waits = [j.sent.wait() for j in self._jogs.values() if j.stopping is not None]
        if waits:
            await asyncio.gather(*waits)

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
        jog.deadline = loop.time() + jog.info.keepalive_ms / 1000
        jog.timer = loop.call_later(jog.info.keepalive_ms / 1000, self._expired, jog, False)

    def _expired(self, jog: _Jog, listened: bool) -> None:
        if jog.info.state != "running":
            return
        loop = asyncio.get_running_loop()
        if not listened and loop.time() - jog.deadline > LATE_S:
            # The server, not the page, was late: a stall of the loop (a busy host) would
            # otherwise stop an axis whose keep-alives all came in time. Bounded: the axis
            # stops at most LISTEN_S after the stall when none is there.
            jog.timer = loop.call_later(LISTEN_S, self._expired, jog, True)
            return
        self._stop(jog, Reason("stop.keepalive", ms=jog.info.keepalive_ms), by_tool=True)

    def _disarm(self, jog: _Jog) -> None:
        if jog.timer is not None:
            jog.timer.cancel()
            jog.timer = None
        watch, jog.watch = jog.watch, None
        if watch is not None and watch is not asyncio.current_task():
            watch.cancel()

    def _update(self, jog: _Jog, **changes: object) -> None:
        if "stop_reason" in changes:  # the reason's words by id too, for the page
            reason = changes["stop_reason"]
            jog.reason = reason if isinstance(reason, str) else ""
            message_id, params = said(reason if isinstance(reason, str) else None)
            changes.update(stop_reason=str(reason), stop_reason_id=message_id)
            changes["stop_reason_params"] = params
        jog.info = jog.info.model_copy(update=changes)
        self._nodes_changed()
        for fn in list(self._listeners):
            fn(jog.info)

    def _retire(self, jog: _Jog) -> None:
        """Ended without a stop: a new jog of the node took the axis over."""
        self._disarm(jog)
        jog.sent.set()
        self._update(jog, state="stopped", stop_reason=REPLACED)

    def _stop(self, jog: _Jog, reason: str, *, by_tool: bool = False) -> JogInfo:
        if jog.info.state != "running":
            return jog.info
        self._disarm(jog)
        self._update(jog, state="stopping", stop_reason=reason)
        jog.stopping = asyncio.get_running_loop().create_task(
            self._bring_to_rest(jog, reason, by_tool), name=f"jog stop node {jog.info.node}"
        )
        return jog.info

    async def _bring_to_rest(self, jog: _Jog, reason: str, by_tool: bool) -> None:
        node = jog.info.node
        try:
            sent = await self._send_stop(jog, reason, by_tool)
        finally:
            jog.sent.set()
        if not sent:
            self._update(
                jog,
                state="stopped",
                stop_reason=then(reason, "stop.then_not_sent"),
            )
            return
        note = await self._watch_to_rest(jog, node)
        update: dict[str, object] = {"state": "stopped"}
        if note:
            update["stop_reason"] = then(reason, note[0], **note[1])
        self._update(jog, **update)

    async def _send_stop(self, jog: _Jog, reason: str, by_tool: bool) -> bool:
        node = jog.info.node
        entry: AbstractAsyncContextManager[object] = nullcontext()
        if by_tool and self._record is not None:
            entry = self._record("jog-stop", node, f"stop the jog of node {node}: {reason}")
        try:
            async with entry:
                await self._motion.stop(
                    node,
                    reason=reason,
                    deceleration_rpm_s=jog.info.stop_deceleration_rpm_s,
                    # a torque jog has no ramp of its own: it brakes on the drive's quick stop
                    # deceleration, as does every stop the user did not ask for
                    drive_deceleration=by_tool or jog.info.mode == "pt",
                )
        except ServodeskError as error:
            self.unsent.add(node)
            log.warning("node %d: stopping the jog (%s) failed: %s", node, reason, error)
            return False
        self.unsent.discard(node)
        return True

    async def _watch_to_rest(self, jog: _Jog, node: int) -> tuple[str, Params] | None:
        """Read 606Ch until the axis is at rest; a quick stop when it takes longer than its
        deceleration allows. Returns a note for the stop reason (its message id, its own
        parameters) when it did not end plainly."""
        loop = asyncio.get_running_loop()
        decel = jog.info.stop_deceleration_rpm_s or self._floor
        deadline: float | None = None
        quick_sent = False
        still = 0
        while True:
            try:
                rpm = await self._motion.velocity_rpm(node)
            except ServodeskError as error:
                return "stop.then_unread", {"error": str(error)}
            jog.info = jog.info.model_copy(update={"velocity_rpm": rpm})
            still = still + 1 if abs(rpm) < self._rest else 0
            if still >= REST_READINGS:
                return ("stop.then_no_slowdown", {}) if quick_sent else None
            now = loop.time()
            if deadline is None:
                deadline = now + abs(rpm) / decel * STOP_MARGIN + STOP_SLACK
            elif now > deadline and not quick_sent:
                quick_sent = True
                deadline = now + WATCH_AFTER_QUICK_STOP
                log.warning("node %d: not at rest after the halt (%.0f rpm): quick stop", node, rpm)
                try:
                    await self._motion.stop(node, reason="not at rest after the halt", quick=True)
                except ServodeskError as error:
                    return "stop.then_quick_unsent", {"rpm": f"{rpm:.0f}", "error": str(error)}
            elif now > deadline:
                after = f"{WATCH_AFTER_QUICK_STOP:g}"
                return "stop.then_still_moving", {"rpm": f"{rpm:.0f}", "seconds": after}
            await asyncio.sleep(self._interval)

    async def _watch_running(self, jog: _Jog) -> None:
        """While the jog runs: a torque jog's own speed cap, and ServoDesk's travel limits
        (stopped where the deceleration would still end inside them), from 606Ch and 6064h."""
        node = jog.info.node
        cap = jog.info.speed_cap_rpm
        decel = jog.info.stop_deceleration_rpm_s or self._floor
        while jog.info.state == "running":
            try:
                rpm, rev = await self._motion.reading(node)
            except ServodeskError as error:  # the other triggers handle a lost bus or node
                log.debug("node %d: jog watch reading failed: %s", node, error)
            else:
                jog.info = jog.info.model_copy(update={"velocity_rpm": rpm})
                reason = None
                if cap is not None and abs(rpm) > cap:
                    reason = f"speed cap {cap:g} rpm passed ({abs(rpm):.0f} rpm)"
                else:
                    reach = rpm * abs(rpm) / (120 * decel) + rpm / 60 * (self._interval + 0.05)
                    reason = travel_end(rev, reach, self._motion.travel(node))
                if reason is not None and jog.info.state == "running":
                    self._stop(jog, reason, by_tool=True)
                    return
            await asyncio.sleep(self._interval)

    def _nodes_changed(self) -> None:
        self.running_nodes = frozenset(jog.info.node for jog in self._running())

    def _forget_old(self) -> None:
        stopped = [k for k, j in self._jogs.items() if j.info.state == "stopped"]
        for key in stopped[: max(0, len(stopped) - KEEP_STOPPED)]:
            del self._jogs[key]


def travel_end(rev: float, reach: float, limits: tuple[float | None, float | None]) -> str | None:
    """Why to stop now, if braking from `rev` (the axis still covers `reach` rev, signed)
    would end beyond ServoDesk's travel limits."""
    low, high = limits
    end = rev + reach
    if high is not None and reach > 0 and end >= high:
        return f"ServoDesk's travel limit {high:g} rev ahead (at {rev:.3f} rev)"
    if low is not None and reach < 0 and end <= low:
        return f"ServoDesk's travel limit {low:g} rev ahead (at {rev:.3f} rev)"
    return None
