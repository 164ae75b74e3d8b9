"""Live NMT state and heartbeat age per node, and the events when nodes boot, vanish, return.

Two halves (DESIGN rule 1):
- `FrameWatch`, a python-can listener on the notifier thread: per node, the time and state of
  the last heartbeat/boot-up frame and the time of the last other frame the node sent (dict
  assignments only). A boot-up is also handed to the event loop (`call_soon_threadsafe`).
- `NodeMonitor`, on the event loop: what the registry learned through SDO (answers, timeouts,
  1017h), the NMT commands it sent, a ~5 Hz task that derives each node's health
  (network/health.py) and emits "node-lost" / "node-back", and `wait_boot`.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import time
from collections.abc import Callable
from dataclasses import dataclass

import can

from servodesk.events.bus import BusEvent, EventKind
from servodesk.events.texts import Said, say
from servodesk.models.nodes import NmtStateName
from servodesk.network.health import Evidence, Health, assess, reported_state
from servodesk.network.nmt import BOOT_UP
from servodesk.settings import Settings
from servodesk_protocol import cob_id

log = logging.getLogger(__name__)

TICK = 0.2  # s between health evaluations (the WebSocket sends node states at 5 Hz)
# frames only the node itself sends: EMCY, TPDO1–4 (default COB-IDs), SDO answers
SIGNS_OF_LIFE = frozenset({cob_id.EMCY, *cob_id.TPDOS, cob_id.SDO_TX})

Clock = Callable[[], float]
# A frame's adapter time stamp (UNIX time) is trusted when it lies this close to the wall clock:
# up to STAMP_PAST_S before now (the notifier thread took it late), up to STAMP_AHEAD_S after
# (a simulated burst stamped back to back). Outside that, an adapter with its own epoch: now.
STAMP_PAST_S = 2.0
STAMP_AHEAD_S = 0.1


class FrameWatch(can.Listener):
    """Notifier-thread recorder of heartbeats, boot-ups and other frames, per node."""

    def __init__(self, clock: Clock = time.monotonic, wall: Clock = time.time) -> None:
        self._clock = clock
        self._wall = wall
        self.beats: dict[int, tuple[float, int]] = {}  # node -> (time, state byte)
        self.activity: dict[int, float] = {}  # node -> time of its last non-heartbeat frame
        self.on_boot: Callable[[int, float], None] | None = None  # must not block

    def on_message_received(self, msg: can.Message) -> None:
        if msg.is_error_frame or msg.is_remote_frame or msg.is_extended_id:
            return
        function, node = cob_id.split(msg.arbitration_id)
        if node == 0:
            return
        if function == cob_id.HEARTBEAT:
            if not msg.data:
                return
            now = self._arrival(msg)
            state = msg.data[0] & 0x7F  # bit 7 is the node-guarding toggle
            self.beats[node] = (now, state)
            callback = self.on_boot
            if state == BOOT_UP and callback is not None:
                callback(node, now)
        elif function in SIGNS_OF_LIFE:
            self.activity[node] = self._arrival(msg)

    def _arrival(self, msg: can.Message) -> float:
        """When the frame was on the bus, in this watch's clock. A busy interpreter hands the
        notifier's frames over late: a boot-up sent before an NMT stop but taken after it
        must not count as newer than the stop (network.health.reported_state). The adapter's
        time stamp does not move with the thread, so it decides where it is plausible."""
        now = self._clock()
        age = self._wall() - msg.timestamp
        if -STAMP_AHEAD_S <= age <= STAMP_PAST_S:
            return now - max(age, 0.0)
        return now

    def forget(self) -> None:
        # new dicts rather than clear(): the notifier thread may be writing to the old ones
        self.beats = {}
        self.activity = {}

    def stop(self) -> None:
        """Nothing to release: the watch outlives each connection's notifier."""


@dataclass
class _Tracked:
    """What the tool itself learned about one registered node (event-loop side)."""

    heartbeat_ms: int | None
    expect_since: float
    alive_at: float
    silence_at: float | None = None
    command: tuple[float, NmtStateName] | None = None
    online: bool = True  # as last reported (events fire on changes)


@dataclass
class _BootWaiter:
    since: float
    future: asyncio.Future[None]


class NodeMonitor:
    def __init__(
        self,
        settings: Settings,
        emit: Callable[[BusEvent], None],
        *,
        on_boot: Callable[[int], None] | None = None,
        clock: Clock = time.monotonic,
        wall: Clock = time.time,
    ) -> None:
        self._settings = settings
        self._emit = emit
        self._on_boot_hook = on_boot
        self._clock = clock
        self._wall = wall
        self.watch = FrameWatch(clock, wall)
        self.watch.on_boot = self._boot_from_thread
        self._nodes: dict[int, _Tracked] = {}
        self._waiters: dict[int, list[_BootWaiter]] = {}
        self._loop: asyncio.AbstractEventLoop | None = None
        self._task: asyncio.Task[None] | None = None

    # ------------------------------------------------------------------ lifecycle

    def attach_loop(self) -> None:
        """Remember the running loop (boot-ups are handed to it); call on the loop."""
        if self._loop is None:
            self._loop = asyncio.get_running_loop()

    def start(self) -> None:
        """Start the ~5 Hz evaluation task (idempotent); call on the loop."""
        self.attach_loop()
        if self._task is None or self._task.done():
            self._task = asyncio.get_running_loop().create_task(self._run(), name="node-monitor")

    def stop_soon(self) -> None:
        """Cancel the evaluation task without waiting (from a synchronous callback)."""
        if self._task is not None:
            self._task.cancel()
            self._task = None

    async def stop(self) -> None:
        task, self._task = self._task, None
        if task is not None:
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await task

    def forget(self) -> None:
        """Drop everything known (bus disconnected); boot waiters keep waiting."""
        self._nodes.clear()
        self.watch.forget()

    async def _run(self) -> None:
        while True:
            await asyncio.sleep(TICK)
            self.tick()

    # ------------------------------------------------------------------ what the registry tells

    def track(self, node: int, heartbeat_ms: int | None) -> None:
        """The node answered its identification just now."""
        now = self._clock()
        previous = self._nodes.get(node)
        self._nodes[node] = _Tracked(
            heartbeat_ms=heartbeat_ms,
            expect_since=now,
            alive_at=now,
            command=previous.command if previous is not None else None,
        )
        if previous is not None and not previous.online:
            self._event(EventKind.NODE_BACK, node, say("event.answers_again", node=node))

    def untrack(self, node: int) -> None:
        self._nodes.pop(node, None)

    def tracked(self, node: int) -> bool:
        return node in self._nodes

    def heartbeat_known(self, node: int, ms: int) -> None:
        """1017h was read or written: expect heartbeats at this period from now on."""
        tracked = self._nodes.get(node)
        if tracked is not None:
            tracked.heartbeat_ms = ms
            tracked.expect_since = self._clock()

    def heartbeat_ms(self, node: int) -> int | None:
        tracked = self._nodes.get(node)
        return tracked.heartbeat_ms if tracked is not None else None

    def sdo_outcome(self, node: int, answered: bool) -> None:
        """An SDO exchange through the tool got an answer (or an abort), or timed out."""
        tracked = self._nodes.get(node)
        if tracked is None:
            return
        now = self._clock()
        if answered:
            tracked.alive_at = now
        elif self.health(node).nmt_state is not NmtStateName.STOPPED:
            # a node we stopped is expected not to answer SDO: that is no sign of loss
            tracked.silence_at = now

    def absent(self, node: int) -> None:
        """A scan did not find the node."""
        tracked = self._nodes.get(node)
        if tracked is not None:
            tracked.silence_at = self._clock()

    def commanded(self, node: int, state: NmtStateName, *, at: float | None = None) -> None:
        """The tool sent an NMT command (at `at`, monitor time; default now)."""
        tracked = self._nodes.get(node)
        if tracked is not None:
            tracked.command = (self._clock() if at is None else at, state)

    def now(self) -> float:
        """The monitor's clock (monotonic seconds)."""
        return self._clock()

    # ------------------------------------------------------------------ what the UI asks

    def evidence(self, node: int) -> Evidence:
        tracked = self._nodes.get(node)
        beat = self.watch.beats.get(node)
        activity = self.watch.activity.get(node)
        if tracked is None:
            return Evidence(beat=beat, activity=activity)
        return Evidence(
            beat=beat,
            activity=activity,
            alive_at=tracked.alive_at,
            silence_at=tracked.silence_at,
            command=tracked.command,
            heartbeat_ms=tracked.heartbeat_ms,
            expect_since=tracked.expect_since,
        )

    def health(self, node: int) -> Health:
        return assess(
            self.evidence(node),
            self._clock(),
            lost_factor=self._settings.heartbeat_lost_factor,
            default_timeout=self._settings.default_heartbeat_timeout,
        )

    def is_stopped(self, node: int) -> bool:
        """`health(node).nmt_state is STOPPED`, asked before every SDO request: the full
        assessment only for a node last reported Stopped."""
        tracked = self._nodes.get(node)
        command = tracked.command if tracked is not None else None
        if reported_state(self.watch.beats.get(node), command) is not NmtStateName.STOPPED:
            return False
        return self.health(node).nmt_state is NmtStateName.STOPPED

    def heard(self) -> set[int]:
        """Nodes whose heartbeat or boot-up has been heard (the passive part of a scan)."""
        return set(self.watch.beats)

    def wall_time(self, monotonic: float | None) -> float | None:
        """A monotonic time of this monitor as UNIX time."""
        if monotonic is None:
            return None
        return self._wall() - (self._clock() - monotonic)

    def tick(self) -> None:
        """Evaluate every node once and emit the changes (the task calls this at 5 Hz)."""
        for node, tracked in list(self._nodes.items()):
            health = self.health(node)
            if health.online == tracked.online:
                continue
            tracked.online = health.online
            if health.online:
                self._event(EventKind.NODE_BACK, node, say("event.back", node=node))
            elif health.lost_after_s is not None:
                limit_ms = round(health.lost_after_s * 1000)
                said = say("event.lost_heartbeat", node=node, limit_ms=limit_ms)
                self._event(EventKind.NODE_LOST, node, said)
            else:
                self._event(EventKind.NODE_LOST, node, say("event.lost_sdo", node=node))

    # ------------------------------------------------------------------ boot-ups

    async def wait_boot(self, node: int, timeout: float) -> bool:
        """True once a boot-up from `node` arrives after this call started (see NodeAccess).

        The waiter is registered before the first suspension point, so a caller may start this
        as a task, yield once, and only then send the reset."""
        self.attach_loop()
        loop = asyncio.get_running_loop()
        waiter = _BootWaiter(since=self._clock(), future=loop.create_future())
        waiters = self._waiters.setdefault(node, [])
        waiters.append(waiter)
        try:
            await asyncio.wait_for(waiter.future, timeout)
        except TimeoutError:
            return False
        finally:
            waiters.remove(waiter)
            if not waiters and self._waiters.get(node) is waiters:
                del self._waiters[node]
        return True

    def _boot_from_thread(self, node: int, when: float) -> None:
        loop = self._loop
        if loop is None or loop.is_closed():
            return  # nobody waits yet; the frame is recorded in `watch.beats`
        try:
            loop.call_soon_threadsafe(self._on_boot, node, when)
        except RuntimeError:
            log.debug("boot-up of node %d after the event loop closed", node)

    def _on_boot(self, node: int, when: float) -> None:
        for waiter in self._waiters.get(node, ()):
            if waiter.since <= when and not waiter.future.done():
                waiter.future.set_result(None)
        known = node in self._nodes
        booted = "event.booted" if known else "event.booted_unscanned"
        self._event(EventKind.BOOT_UP, node, say(booted, node=node))
        if self._on_boot_hook is not None:
            self._on_boot_hook(node)  # known or not: the registry decides

    def _event(self, kind: EventKind, node: int | None, said: Said) -> None:
        self._emit(
            BusEvent(self._wall(), kind, node, said.message, {}, said.message_id, dict(said.params))
        )
