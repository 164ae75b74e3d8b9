"""The motion service's shared machinery: per-node axes, readings, controlword writes, waiting
for the statusword, operating modes, and turning a transition that did not happen into the
reasons from the drive's own objects (explain.py)."""

from __future__ import annotations

import asyncio
import logging
import time
from collections.abc import Callable
from typing import TypeVar

import canopen

from servodesk.errors import CommTimeoutError, NodeStoppedError, SdoAbortError
from servodesk.motion import drive_io as io
from servodesk.motion.axis import Axis, build_state, units_of
from servodesk.motion.drive_io import Snapshot, Statics
from servodesk.motion.errors import EnableBlockedError
from servodesk.motion.explain import Observed, explain
from servodesk.motion.schemas import DriveState, EnableReason, MotionLimits, SpeedLimit
from servodesk.motion.units import DriveUnits
from servodesk.motion.words import mode_key
from servodesk.nodes.access import NodeAccess
from servodesk.nodes.session import StopCutInError
from servodesk.pdo.commands import RpdoRoutes
from servodesk.pdo.feed import TpdoFeeds
from servodesk.settings import Settings
from servodesk_protocol.cia402 import (
    MODES_DISPLAY,
    MODES_OF_OPERATION,
    Cia402State,
    OperationMode,
    decode_state,
    supported_modes,
)

T = TypeVar("T")
log = logging.getLogger(__name__)
VALUE_RANGE = 0x06090030  # SDO abort: value range of parameter exceeded (unsupported 6060h)
FAULT_SOURCES = {
    "mdi-s1c": "MDi-S1-C CANopen manual §4.1",
    "kinco": "Kinco servo CANopen manual §8",
    "cia402": "CiA 301 / CiA 402 emergency codes",
}
DEFAULT_MAX_RPM = 3000.0  # a drive with no overspeed object nor default
DEFAULT_MAX_TORQUE_PCT = 300.0  # 6072h's usual default (3000 = 300 %)


def state_of(statusword: int) -> Cia402State:
    try:
        return decode_state(statusword)
    except ValueError:
        return Cia402State.NOT_READY_TO_SWITCH_ON


class MotionCore:
    def __init__(
        self,
        registry: NodeAccess,
        settings: Settings,
        *,
        on_statusword: Callable[[int, int], None] | None = None,
    ) -> None:
        self._registry = registry
        self._settings = settings
        self._axes: dict[int, Axis] = {}
        self._feeds: TpdoFeeds | None = None  # the drive state from TPDOs (MotionService)
        self._routes: RpdoRoutes | None = None  # commands in RPDOs (MotionService)
        # (node, statusword) after every read of 6041h, on the event loop (the fault service
        # publishes CiA 402 state changes from it)
        self._on_statusword = on_statusword

    # ------------------------------------------------------------------ axes and units

    def _axis(self, node: int) -> Axis:
        axis = self._axes.get(node)
        if axis is None:
            axis = Axis(node=node, limits=self._default_limits(node, None))
            self._axes[node] = axis
        return axis

    def _units(self, node: int) -> DriveUnits:
        return units_of(self._axis(node).statics, self._registry.profile_data(node))

    def _profile(self, node: int) -> str:
        return self._registry.info(node).profile

    def _transition_timeout(self, node: int) -> float:
        by_profile = self._settings.motion_transition_timeouts
        return by_profile.get(self._profile(node), self._settings.motion_transition_timeout)

    def _default_limits(self, node: int, statics: Statics | None) -> MotionLimits:
        """The drive's overspeed object (MDi PA-103 2006h:08, else 6080h) and 6072h, as read or
        as its dictionary's defaults, capped by the settings."""
        data = self._registry.profile_data(node)
        speed_ref = data.quirks.max_speed_object if data else (0x6080, 0)  # Max motor speed
        read_rpm = statics.overspeed_rpm if statics and statics.overspeed_rpm else None
        read_torque = statics.max_torque if statics and statics.max_torque else None
        rpm = float(read_rpm or self._od_default(node, *speed_ref) or DEFAULT_MAX_RPM)
        torque_raw = read_torque or self._od_default(node, io.MAX_TORQUE, 0)
        torque_pct = float(torque_raw) / 10 if torque_raw else DEFAULT_MAX_TORQUE_PCT
        # 6071h's own range caps a torque jog too (MDi-S1-C: ±1000 = 100 % while 6072h
        # allows 300 %): a set-point past it is refused by the drive (abort 06090031h)
        target = self._registry.od(node).get(io.TARGET_TORQUE, 0)
        if target is not None and isinstance(target.high, int | float) and target.high > 0:
            torque_pct = min(torque_pct, float(target.high) / 10)
        if self._settings.motion_max_velocity_rpm:
            rpm = min(rpm, self._settings.motion_max_velocity_rpm)
        if self._settings.motion_max_torque_pct:
            torque_pct = min(torque_pct, self._settings.motion_max_torque_pct)
        return MotionLimits(
            max_velocity_rpm=rpm,
            max_torque_pct=torque_pct,
            min_position_rev=None,
            max_position_rev=None,
        )

    def pt_speed_limit(self, node: int) -> tuple[float | None, str]:
        """What caps the speed in profile torque: (rpm or None when unknown, the object)."""
        index, sub, named = self._speed_object(node)
        statics = self._axis(node).statics
        read = statics.overspeed_rpm if statics and statics.overspeed_rpm else None
        rpm = read or self._od_default(node, index, sub)
        return (float(rpm) if rpm else None), named

    def _speed_object(self, node: int) -> tuple[int, int, str]:
        """The drive's max speed object (MDi PA-103 2006h:08, else 6080h Max motor speed) and
        how the page names it: "2006h:08 PA-103 Maximum speed"."""
        data = self._registry.profile_data(node)
        index, sub = data.quirks.max_speed_object if data else (0x6080, 0)  # Max motor speed
        obj = self._registry.od(node).objects.get(index)
        entry = obj.subs.get(sub) if obj else None
        name = entry.name if entry else (obj.name if obj else "max speed")
        where = f"{index:04X}h:{sub:02X}" if sub else f"{index:04X}h"
        return index, sub, f"{where} {name}"

    def _od_default(self, node: int, index: int, sub: int) -> float | None:
        obj = self._registry.od(node).objects.get(index)
        entry = obj.subs.get(sub) if obj else None
        value = entry.default if entry else None
        return float(value) if isinstance(value, int | float) and value > 0 else None

    # ------------------------------------------------------------------ node access

    async def _run(
        self,
        node: int,
        fn: Callable[[canopen.RemoteNode], T],
        what: str,
        *,
        command: bool = True,
    ) -> T:
        """A step of a motion command or of a jog's watch: ahead of the node's queued reads
        (nodes/session.py). `command=False` for background reading (a page's poll, limits)."""
        return await self._registry.session(node).run(
            fn, what=f"{what} (node {node})", command=command
        )

    async def _write(
        self, node: int, index: int, sub: int, value: int, kind: tuple[int, bool]
    ) -> None:
        """One command object to the drive: in the mapped RPDO where there is one whose other
        objects ServoDesk knows (pdo/commands.py), else by SDO. Refused unsent when a stop
        went to the drive after it was asked for (a queued write must not undo the stop)."""
        axis = self._axis(node)
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
        await self._registry.session(node).run(
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
        data = route.payload({**self._axis(node).sent, index: value})
        return (network, route.cob_id, data, route.label) if data is not None else None

    def forget_sent(self, node: int | None = None) -> None:
        """What ServoDesk wrote may no longer hold: another write, a reset, a stop."""
        axes = self._axes.values() if node is None else [self._axes.get(node)]
        for axis in axes:
            if axis is not None:  # a node never commanded has nothing to forget
                axis.sent.clear()

    async def _controlword(self, node: int, word: int) -> None:
        await self._write(node, 0x6040, 0, word, io.U16)  # Controlword

    async def _statusword(self, node: int) -> int:
        statusword = await self._run(node, io.read_statusword, "read 6041h")
        self._axis(node).sdo_values["statusword"] = (statusword, time.monotonic())
        self._saw_statusword(node, statusword)
        return statusword

    def _saw_statusword(self, node: int, statusword: int) -> None:
        if self._on_statusword is None:
            return
        try:
            self._on_statusword(node, statusword)
        except Exception:  # a listener's failure must never stop a motion command
            log.exception("node %d: statusword listener failed", node)

    async def _snapshot(self, node: int, *, sdo_budget: int | None = None) -> Snapshot:
        """A reading: what the node's TPDOs carry from the frames, the rest by SDO. With an
        `sdo_budget` (the pages' polling) at most that many uploads, the most overdue first
        (POLL_AGE), each other value kept from the last reading until its turn comes."""
        axis = self._axis(node)
        if axis.statics is None:
            await self._refresh_statics(node)
        started = time.monotonic()
        given, sources = self._carried(node, ask=sdo_budget is not None)
        if sdo_budget is not None and axis.last is not None:
            missing = [name for name in io.SNAPSHOT_OBJECTS if name not in given]
            kept = _kept_over(axis, missing, sdo_budget, time.monotonic())
            for name in kept:
                given[name] = getattr(axis.last, name)
                sources[name] = axis.last.sources.get(name, io.SDO)
        if len(given) == len(io.SNAPSHOT_OBJECTS):
            snap = io.snapshot_of(given, sources)  # nothing to ask the drive
        else:
            asked = [name for name in io.SNAPSHOT_OBJECTS if name not in given]
            snap = await self._run(
                node,
                lambda r: io.read_snapshot(r, given, sources),
                "read the drive state",
                command=sdo_budget is None,  # the pages' shared reading waits its turn
            )
            now = time.monotonic()
            axis.sdo_read_at.update((name, now) for name in asked)
            axis.sdo_values.update((name, (getattr(snap, name), now)) for name in asked)
            for name, index in READ_INTO_SENT.items():  # what the drive holds, read just now
                value = getattr(snap, name)
                if name in asked and value is not None:
                    axis.sent[index] = value
        self._saw_statusword(node, snap.statusword)
        if started >= axis.last_at:  # a reading that started earlier keeps older values
            axis.last, axis.last_at = snap, started
            axis.saw(state_of(snap.statusword))
        return snap

    def _carried(
        self, node: int, *, ask: bool = False
    ) -> tuple[dict[str, int | None], dict[str, str]]:
        """The snapshot's objects the node's TPDOs carry now: (values, "TPDOn" by field);
        `ask`: read an unknown mapping in the background (TpdoFeeds.values)."""
        keys = {(index, 0): name for name, (index, _signed) in io.SNAPSHOT_OBJECTS.items()}
        carried = self._feeds.values(node, keys, ask=ask) if self._feeds is not None else {}
        values: dict[str, int | None] = {}
        sources: dict[str, str] = {}
        axis = self._axis(node)
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

    async def _refresh_statics(self, node: int) -> None:
        data = self._registry.profile_data(node)
        speed_ref = data.quirks.max_speed_object if data else (0x6080, 0)  # Max motor speed
        statics = await self._run(
            node, lambda r: io.read_statics(r, speed_ref), "read drive facts", command=False
        )
        axis = self._axis(node)
        first = axis.statics is None
        axis.statics = statics
        if first:  # user-set limits stay; the first contact replaces dictionary defaults
            axis.limits = self._default_limits(node, statics)

    def _nmt(self, node: int) -> str:
        return str(self._registry.info(node).nmt_state)

    def _build(self, node: int, snap: Snapshot) -> DriveState:
        data = self._registry.profile_data(node)
        rpm, source = self.pt_speed_limit(node)
        return build_state(
            self._axis(node),
            snap,
            nmt_state=self._nmt(node),
            data=data,
            fault_source=FAULT_SOURCES.get(data.profile if data else "", "CiA 402"),
            pt_speed_limit=SpeedLimit(rpm=rpm, source=source),
        )

    async def state(self, node: int) -> DriveState:
        """The drive now: statusword bit by bit, state, mode, position, velocity, torque…"""
        return self._build(node, await self._snapshot(node))

    def _unreadable_state(self, node: int) -> DriveState:
        """The last reading (or an empty one) when the drive does not answer."""
        axis = self._axis(node)
        snap = axis.last or Snapshot(0, None, None, None, None, None, None, None, None, None, {})
        return self._build(node, snap)

    # ------------------------------------------------------------------ waiting, explaining

    async def _wait(
        self, node: int, done: Callable[[int], bool], timeout: float
    ) -> tuple[bool, int]:
        """Poll 6041h until `done(statusword)`; (reached, last statusword)."""
        deadline = time.monotonic() + timeout
        while True:
            sw = await self._statusword(node)
            if done(sw) or time.monotonic() >= deadline:
                self._axis(node).saw(state_of(sw))
                return done(sw), sw
            await asyncio.sleep(self._settings.motion_poll_interval)

    async def _blocked(
        self,
        node: int,
        *,
        extra: list[EnableReason] | None = None,
        target: Cia402State = Cia402State.OPERATION_ENABLED,
        goal: str = "enable",
    ) -> EnableBlockedError:
        """The error for a transition that did not happen, with what the drive shows."""
        nmt = self._nmt(node)
        try:
            snap: Snapshot | None = await self._snapshot(node)
        except (CommTimeoutError, NodeStoppedError):
            snap = None
        axis = self._axis(node)
        data = self._registry.profile_data(node)
        supported = (
            frozenset(int(m) for m in supported_modes(axis.statics.supported_raw))
            if axis.statics and axis.statics.supported_raw is not None
            else None
        )
        state = self._build(node, snap) if snap else self._unreadable_state(node)
        seen = Observed(
            statusword=snap.statusword if snap else None,
            controlword=snap.controlword if snap else None,
            nmt_state=nmt,
            mode=snap.mode if snap else None,
            mode_display=snap.mode_display if snap else None,
            supported=supported
            if supported is not None
            else (data.quirks.supported_modes if data else None),
            fault=state.fault,
            target=target,
        )
        reasons = [*(extra or []), *explain(seen)]
        if extra and len(reasons) > len(extra) and reasons[-1].code == "timeout":
            reasons.pop()  # the extra reason already says why
        return EnableBlockedError(node, reasons, state, goal=goal)

    # ------------------------------------------------------------------ modes

    async def _set_mode(self, node: int, mode: OperationMode) -> None:
        """Write 6060h and wait until 6061h shows it; an unsupported mode raises
        EnableBlockedError(mode_unsupported) — SDO abort on Kinco/CiA 402, 6061h = 0 on MDi."""
        try:
            await self._write(node, MODES_OF_OPERATION, 0, int(mode), io.I8)
        except SdoAbortError as abort:
            if abort.code != VALUE_RANGE:
                raise
            raise await self._blocked(
                node, extra=[_unsupported(mode, "the drive refused it (SDO abort 06090030h)")]
            ) from abort
        deadline = time.monotonic() + self._transition_timeout(node)
        while True:
            shown = self._carried(node)[0].get("mode_display")  # a TPDO carrying 6061h
            if shown is None:
                shown = await self._run(
                    node, lambda r: io.read(r, MODES_DISPLAY, signed=True), "read 6061h"
                )
                self._axis(node).sdo_values["mode_display"] = (shown, time.monotonic())
            if shown == mode:
                return
            if time.monotonic() >= deadline:
                raise await self._blocked(
                    node,
                    extra=[_unsupported(mode, f"6061h shows {shown} after 6060h = {int(mode)}")],
                )
            await asyncio.sleep(self._settings.motion_poll_interval)


# Command objects a reading holds: read by SDO, they are as known as what ServoDesk wrote (an
# RPDO that maps them beside a set-point can then be sent, pdo/commands.py)
READ_INTO_SENT = {"controlword": 0x6040, "mode": MODES_OF_OPERATION}
STATE_OBJECTS = frozenset({0x6040, MODES_OF_OPERATION})  # a write changes what the drive shows
WRITTEN = "written"  # a value's source: what ServoDesk wrote and the drive confirmed

# How old a value read by SDO may grow in the pages' polling before its turn comes (s): the
# statusword every reading, what moves with the axis often, the rest now and then.
POLL_AGE = {
    "statusword": 0.1,
    "position": 0.1,
    "velocity": 0.1,
    "torque": 0.3,
    "following_error": 0.3,
    "mode_display": 0.5,
    "error_code": 0.5,
    "inputs": 0.5,
    "controlword": 1.0,
    "mode": 1.0,
}


def _kept_over(axis: Axis, missing: list[str], budget: int, now: float) -> list[str]:
    """Of the objects only SDO can read, those this polled reading keeps from the last one:
    all but the `budget` most overdue (age against POLL_AGE; never read: first)."""

    def overdue(name: str) -> float:
        if name == "statusword":  # every reading: the state the page shows
            return float("inf")
        read_at = axis.sdo_read_at.get(name)
        return 1e9 if read_at is None else (now - read_at) / POLL_AGE.get(name, 1.0)

    chosen = sorted(missing, key=overdue, reverse=True)[:budget]
    return [name for name in missing if name not in chosen]


def _unsupported(mode: OperationMode, detail: str) -> EnableReason:
    return EnableReason(
        code="mode_unsupported",
        message=f"mode {mode_key(int(mode))} ({int(mode)}) is not supported by this drive: "
        f"{detail}",
    )
