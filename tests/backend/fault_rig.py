"""Fault-injection rig: a python-can bus wrapper that loses, holds back, repeats or alters the
frames a test picks, goes silent, or fails like a lost adapter, and comes back.

`FaultRig.factory` is a `BusFactory`: hand it to `create_app(bus_factory=…)` or
`BusManager(bus_factory=…)`. Every bus the manager opens (again after each reconnect) is wrapped
around a python-can `virtual` bus of the channel asked for and shares the rig's rules, so a test
changes the faults at any time from its own thread. Only the tool's side of the bus is wrapped:
the simulated drives talk normally, the tool hears (and is heard) through the faults.

Directions: "rx" are frames the tool receives (the drives' answers, heartbeats, EMCYs), "tx"
the frames it sends (SDO requests, NMT, its heartbeat).
"""

from __future__ import annotations

import contextlib
import heapq
import itertools
import threading
import time
from collections.abc import Awaitable, Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Any, Literal, TypeVar

import can
import httpx
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.models.bus import BusConfig
from servodesk.services import Services
from servodesk.settings import Settings
from servodesk_sim.frames import Frame

T = TypeVar("T")
Direction = Literal["rx", "tx"]
Match = Callable[[can.Message], bool]
Hook = Callable[[can.Message], None]

SDO_TX = 0x580  # SDO response base COB-ID (server → client)
SDO_RX = 0x600  # SDO request base COB-ID (client → server)
HEARTBEAT = 0x700  # NMT error control base COB-ID
NMT = 0x000
RESET_NODE = 0x81  # NMT command specifier
SEGMENT_UPLOAD_RESPONSE = 0x00  # scs 0 (bits 7–5) of an upload segment response
INITIATE_UPLOAD_REQUEST = 0x40


class Action(Enum):
    PASS = "pass"  # the frame passes; only the rule's `then` runs
    DROP = "drop"  # the frame is lost
    DELAY = "delay"  # the frame arrives `delay` s later (other frames overtake it)
    DUPLICATE = "duplicate"  # the frame arrives twice (the copy after `delay` s)
    REPLACE = "replace"  # `transform` gives the frame that arrives instead


@dataclass
class Rule:
    """What happens to the frames `match` picks: the first `skip` pass, then the next `times`
    (all when None) get `action`; `then` is called with each frame acted on (on the bus's
    thread: notifier for rx, sender for tx), e.g. to make a drive reset at that moment."""

    direction: Direction
    match: Match
    action: Action
    delay: float = 0.0
    skip: int = 0
    times: int | None = None
    transform: Callable[[can.Message], can.Message] | None = None
    then: Hook | None = None
    seen: int = 0  # frames matched so far
    hits: int = 0  # frames acted on so far

    def take(self, msg: can.Message) -> bool:
        """Whether this rule acts on `msg` (counts it); called under the rig's lock."""
        if not self.match(msg):
            return False
        self.seen += 1
        if self.seen <= self.skip or (self.times is not None and self.hits >= self.times):
            return False
        self.hits += 1
        return True


@dataclass
class FaultRig:
    """The rules and switches shared by every bus the factory opened."""

    rules: list[Rule] = field(default_factory=list)
    opened: int = 0  # buses the factory built
    _lock: threading.Lock = field(default_factory=threading.Lock)
    _unplugged: threading.Event = field(default_factory=threading.Event)
    _silent: threading.Event = field(default_factory=threading.Event)

    # ------------------------------------------------------------------ the factory

    def factory(self, config: BusConfig) -> can.BusABC:
        if self._unplugged.is_set():
            raise can.CanInitializationError("injected: the adapter is unplugged")
        with self._lock:
            self.opened += 1
        return FaultyBus(can.Bus(interface="virtual", channel=config.channel), self)

    # ------------------------------------------------------------------ faults

    def add(self, rule: Rule) -> Rule:
        with self._lock:
            self.rules.append(rule)
        return rule

    def remove(self, rule: Rule) -> None:
        with self._lock:
            if rule in self.rules:
                self.rules.remove(rule)

    def clear(self) -> None:
        with self._lock:
            self.rules.clear()

    def on(self, direction: Direction, match: Match, then: Hook, **options: Any) -> Rule:
        """Call `then` when a matching frame passes (it is not altered)."""
        return self.add(Rule(direction, match, Action.PASS, then=then, **options))

    def drop(self, direction: Direction, match: Match, **options: Any) -> Rule:
        return self.add(Rule(direction, match, Action.DROP, **options))

    def delay(self, direction: Direction, match: Match, seconds: float, **options: Any) -> Rule:
        return self.add(Rule(direction, match, Action.DELAY, delay=seconds, **options))

    def duplicate(self, direction: Direction, match: Match, **options: Any) -> Rule:
        return self.add(Rule(direction, match, Action.DUPLICATE, **options))

    def replace(
        self,
        direction: Direction,
        match: Match,
        transform: Callable[[can.Message], can.Message],
        **options: Any,
    ) -> Rule:
        return self.add(Rule(direction, match, Action.REPLACE, transform=transform, **options))

    def unplug(self) -> None:
        """Every send and receive raises like a lost adapter; opening a new bus fails."""
        self._unplugged.set()

    def plug(self) -> None:
        self._unplugged.clear()

    @property
    def unplugged(self) -> bool:
        return self._unplugged.is_set()

    def go_silent(self) -> None:
        """The adapter stays open but no frame passes in either direction (a cut cable)."""
        self._silent.set()

    def speak(self) -> None:
        self._silent.clear()

    @property
    def silent(self) -> bool:
        return self._silent.is_set()

    def pick(self, direction: Direction, msg: can.Message) -> Rule | None:
        """The first rule that acts on `msg`, if any."""
        with self._lock:
            for rule in self.rules:
                if rule.direction == direction and rule.take(msg):
                    return rule
        return None


class FaultyBus(can.BusABC):
    """A virtual bus with the rig's faults applied to what passes through it."""

    def __init__(self, inner: can.BusABC, rig: FaultRig) -> None:
        self.inner = inner
        self.rig = rig
        self.channel_info = f"faulty {inner.channel_info}"
        self._held: list[tuple[float, int, can.Message]] = []  # received, not yet due
        self._order = itertools.count()
        self._timers: set[threading.Timer] = set()
        self._timers_lock = threading.Lock()
        super().__init__(channel=inner.channel_info)

    # ------------------------------------------------------------------ receive

    def _recv_internal(self, timeout: float | None) -> tuple[can.Message | None, bool]:
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            if self.rig.unplugged:
                raise can.CanOperationError("injected: the adapter was lost (recv)")
            now = time.monotonic()
            if self._held and self._held[0][0] <= now:
                return heapq.heappop(self._held)[2], True
            wait = None if deadline is None else max(0.0, deadline - now)
            if self._held:
                until_due = self._held[0][0] - now
                wait = until_due if wait is None else min(wait, until_due)
            msg = self.inner.recv(wait)
            if msg is not None:
                passed = self._apply_rx(msg)
                if passed is not None:
                    return passed, True
            elif deadline is not None and time.monotonic() >= deadline and not self._due():
                return None, True

    def _due(self) -> bool:
        return bool(self._held) and self._held[0][0] <= time.monotonic()

    def _hold(self, msg: can.Message, delay: float) -> None:
        heapq.heappush(self._held, (time.monotonic() + delay, next(self._order), msg))

    def _apply_rx(self, msg: can.Message) -> can.Message | None:
        if self.rig.silent:
            return None
        rule = self.rig.pick("rx", msg)
        if rule is None:
            return msg
        if rule.then is not None:
            rule.then(msg)
        if rule.action is Action.PASS:
            return msg
        if rule.action is Action.DROP:
            return None
        if rule.action is Action.DELAY:
            self._hold(msg, rule.delay)
            return None
        if rule.action is Action.DUPLICATE:
            self._hold(_copy(msg), rule.delay)
            return msg
        return _transformed(rule, msg)

    # ------------------------------------------------------------------ send

    def send(self, msg: can.Message, timeout: float | None = None) -> None:
        if self.rig.unplugged:
            raise can.CanOperationError("injected: the adapter was lost (send)")
        if self.rig.silent:
            return
        rule = self.rig.pick("tx", msg)
        if rule is None:
            self.inner.send(msg, timeout)
            return
        if rule.then is not None:
            rule.then(msg)
        if rule.action is Action.PASS:
            self.inner.send(msg, timeout)
            return
        if rule.action is Action.DROP:
            return
        if rule.action is Action.DELAY:
            self._later(_copy(msg), rule.delay)
            return
        if rule.action is Action.DUPLICATE:
            self.inner.send(msg, timeout)
            self._later(_copy(msg), rule.delay)
            return
        self.inner.send(_transformed(rule, msg), timeout)

    def _later(self, msg: can.Message, delay: float) -> None:
        def fire() -> None:
            with self._timers_lock:
                self._timers.discard(timer)
            # the bus closed meanwhile: the frame is lost, as on a real bus
            with contextlib.suppress(can.CanError, ValueError):
                self.inner.send(msg)

        timer = threading.Timer(delay, fire)
        timer.daemon = True
        with self._timers_lock:
            self._timers.add(timer)
        timer.start()

    def shutdown(self) -> None:
        with self._timers_lock:
            timers, self._timers = set(self._timers), set()
        for timer in timers:
            timer.cancel()
        super().shutdown()
        self.inner.shutdown()


def _transformed(rule: Rule, msg: can.Message) -> can.Message:
    if rule.transform is None:
        raise ValueError("a REPLACE rule needs a transform")
    return rule.transform(msg)


def _copy(msg: can.Message) -> can.Message:
    return can.Message(
        timestamp=msg.timestamp,
        arbitration_id=msg.arbitration_id,
        is_extended_id=msg.is_extended_id,
        is_remote_frame=msg.is_remote_frame,
        dlc=msg.dlc,
        data=bytes(msg.data),
    )


# ---------------------------------------------------------------------- frame predicates


def sdo_response(node: int) -> Match:
    return lambda msg: msg.arbitration_id == SDO_TX + node


def sdo_request(node: int) -> Match:
    return lambda msg: msg.arbitration_id == SDO_RX + node


def segment_response(node: int) -> Match:
    """Upload segment responses of `node` (scs 0, not an abort)."""

    def match(msg: can.Message) -> bool:
        return (
            msg.arbitration_id == SDO_TX + node
            and len(msg.data) == 8
            and msg.data[0] & 0xE0 == SEGMENT_UPLOAD_RESPONSE
        )

    return match


def heartbeat_of(node: int) -> Match:
    return lambda msg: msg.arbitration_id == HEARTBEAT + node and not msg.is_remote_frame


def with_data(msg: can.Message, data: bytes) -> can.Message:
    """`msg` carrying other bytes (same id)."""
    return can.Message(
        timestamp=msg.timestamp,
        arbitration_id=msg.arbitration_id,
        is_extended_id=msg.is_extended_id,
        data=data,
    )


# ---------------------------------------------------------------------- the app behind it


def fault_settings(data_dir: Path, **overrides: Any) -> Settings:
    """Simulated mode with short timeouts: a failure path takes tenths of a second."""
    values: dict[str, Any] = {
        "simulated": True,
        "data_dir": data_dir,
        "sdo_timeout": 0.2,
        "reconnect_initial_delay": 0.05,
        "reconnect_max_delay": 0.2,
        "default_heartbeat_timeout": 1.0,
        "motion_transition_timeout": 0.5,
        "boot_wait": 2.0,
        "scope_live_view": False,
    }
    values.update(overrides)
    return Settings(**values)


@dataclass
class FaultyApp:
    client: TestClient
    rig: FaultRig

    @property
    def services(self) -> Services:
        found: Services = self.client.app.state.services  # type: ignore[attr-defined]
        return found

    def inject(self, can_id: int, data: bytes) -> None:
        """A frame from another device on the simulated bus (thread-safe)."""
        sim = self.services.bus.sim
        if sim is None:
            raise RuntimeError("no simulated drives")
        sim.inject(Frame(can_id, data))

    def reset_node(self, node: int) -> None:
        """The drive restarts (as after a power glitch): it sends its boot-up again."""
        self.inject(NMT, bytes([RESET_NODE, node]))

    def call(self, fn: Callable[[], Awaitable[T]]) -> T:
        """Await `fn()` on the app's event loop (where its services live)."""

        async def run() -> T:
            return await fn()

        portal = self.client.portal
        if portal is None:
            raise RuntimeError("the app is not running")
        return portal.call(run)

    def timed(self, method: str, url: str, **kwargs: Any) -> tuple[httpx.Response, float]:
        """The answer and how long it took (s)."""
        started = time.monotonic()
        answer = self.client.request(method, url, **kwargs)
        return answer, time.monotonic() - started

    def eventually(
        self, condition: Callable[[], bool], *, timeout: float = 5.0, what: str = "condition"
    ) -> None:
        deadline = time.monotonic() + timeout
        while not condition():
            if time.monotonic() > deadline:
                raise AssertionError(f"{what} did not happen within {timeout} s")
            time.sleep(0.02)


@contextmanager
def faulty_app(data_dir: Path, **settings: Any) -> Iterator[FaultyApp]:
    """The app in simulated mode, its own side of the bus behind a FaultRig."""
    rig = FaultRig()
    app = create_app(fault_settings(data_dir, **settings), static_dir=None, bus_factory=rig.factory)
    with TestClient(app) as client:
        try:
            yield FaultyApp(client, rig)
        finally:
            rig.clear()
            rig.speak()
            rig.plug()
