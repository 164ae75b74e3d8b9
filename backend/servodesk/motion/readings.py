"""What the drive shows: a reading (TPDOs first, the rest by SDO) and the DriveState built from
it, the pages' shared poll, the jog watch's velocity and position, waiting for the statusword or
for 6061h to show a mode, and turning a transition that did not happen into the reasons from the
drive's own objects (explain.py)."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Callable
from dataclasses import replace

import canopen

from servodesk.errors import CommTimeoutError, NodeStoppedError, SdoAbortError
from servodesk.models.motion import DriveState, EnableReason, SpeedLimit
from servodesk.motion import drive_io as io
from servodesk.motion.axis import Axis, build_state
from servodesk.motion.core import READ_INTO_SENT, DriveIo, state_of
from servodesk.motion.drive_io import Snapshot
from servodesk.motion.drive_limits import Limits
from servodesk.motion.errors import EnableBlockedError
from servodesk.motion.explain import Observed, explain
from servodesk.motion.reason_texts import reason
from servodesk.motion.words import mode_key
from servodesk_protocol.cia402 import (
    MODES_DISPLAY,
    MODES_OF_OPERATION,
    Cia402State,
    OperationMode,
    supported_modes,
)
from servodesk_protocol.sdo_abort import INVALID_VALUE

FAULT_SOURCES = {
    "mdi-s1c": "MDi-S1-C CANopen manual §4.1",
    "kinco": "Kinco servo CANopen manual §8",
    "cia402": "CiA 301 / CiA 402 emergency codes",
}
FAULT_SOURCES_ZH = {
    "mdi-s1c": "MDi-S1-C CANopen 手册 §4.1",
    "kinco": "步科伺服 CANopen 手册 §8",
    "cia402": "CiA 301 / CiA 402 紧急报文代码",
}


class Readings:
    """What the drive shows now, and waiting for it to show something else."""

    def __init__(self, drive: DriveIo, limits: Limits) -> None:
        self._drive, self._limits = drive, limits

    def transition_timeout(self, node: int) -> float:
        """How long the drive's profile takes for a state transition (settings)."""
        by_profile = self._drive.settings.motion_transition_timeouts
        profile = self._drive.registry.info(node).profile
        return by_profile.get(profile, self._drive.settings.motion_transition_timeout)

    def nmt(self, node: int) -> str:
        return str(self._drive.registry.info(node).nmt_state)

    # ------------------------------------------------------------------ readings

    async def snapshot(self, node: int, *, sdo_budget: int | None = None) -> Snapshot:
        """A reading: what the node's TPDOs carry from the frames, the rest by SDO. With an
        `sdo_budget` (the pages' polling) at most that many uploads, the most overdue first
        (POLL_AGE), each other value kept from the last reading until its turn comes. The
        drive's own limits are refreshed first when due (Limits.before_reading)."""
        sdo_budget = await self._limits.before_reading(node, sdo_budget)
        axis = self._drive.axis(node)
        if axis.statics is None:
            await self._limits.refresh_statics(node)
        started = time.monotonic()
        given, sources = self._drive.carried(node, ask=sdo_budget is not None)
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
            snap = await self._drive.run(
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
        snap = replace(snap, taken_at=started)
        self._drive.saw_statusword(node, snap.statusword)
        if started >= axis.last_at:  # a reading that started earlier keeps older values
            axis.last, axis.last_at = snap, started
            axis.saw(state_of(snap.statusword))
        return snap

    async def polled_state(self, node: int) -> DriveState:
        """The drive state the pages poll: one reading per `drive_poll_period` shared by every
        caller, its SDO part within `drive_poll_sdo_budget` uploads (what TPDOs carry is
        current in every reading)."""
        axis = self._drive.axis(node)
        async with axis.poll_lock:
            if axis.polled is not None and (
                time.monotonic() - axis.polled_at < self._drive.settings.drive_poll_period
            ):
                return axis.polled
            started = time.monotonic()
            snap = await self.snapshot(node, sdo_budget=self._drive.settings.drive_poll_sdo_budget)
            state = self.build(node, snap)
            if started >= axis.commanded_at:  # not shared when a command came meanwhile
                axis.polled, axis.polled_at = state, time.monotonic()
            return state

    async def velocity_rpm(self, node: int) -> float:
        """606Ch now, in rpm: from a TPDO carrying it, else one upload on the node's queue
        (the jog watchdog's reading)."""
        given, _ = self._drive.carried(node)
        raw = given.get("velocity")
        if "velocity" not in given:
            raw = await self._drive.run(
                node, lambda r: io.read(r, io.VELOCITY_ACTUAL, signed=True), "read 606Ch"
            )
        return self._drive.units(node).actual_velocity_rpm(raw or 0)

    async def reading(self, node: int) -> tuple[float, float]:
        """606Ch (rpm) and 6064h (rev): what a jog's watch needs for its speed cap and
        ServoDesk's travel limits; from TPDOs carrying them, the rest in one step by SDO."""
        given, _ = self._drive.carried(node)

        def read(remote: canopen.RemoteNode) -> tuple[int | None, int | None]:
            velocity = (
                given["velocity"]
                if "velocity" in given
                else io.read(remote, io.VELOCITY_ACTUAL, signed=True)
            )
            position = (
                given["position"]
                if "position" in given
                else io.read(remote, io.POSITION_ACTUAL, signed=True)
            )
            return velocity, position

        if "velocity" in given and "position" in given:
            velocity, position = given["velocity"], given["position"]
        else:
            velocity, position = await self._drive.run(node, read, "read 606Ch and 6064h")
        units = self._drive.units(node)
        rev = units.inc_to_rev(units.user_to_inc(position or 0))
        return units.actual_velocity_rpm(velocity or 0), rev

    def build(self, node: int, snap: Snapshot) -> DriveState:
        data = self._drive.registry.profile_data(node)
        rpm, source = self._limits.pt_speed_limit(node)
        return build_state(
            self._drive.axis(node),
            snap,
            nmt_state=self.nmt(node),
            data=data,
            fault_source=FAULT_SOURCES.get(data.profile if data else "", "CiA 402"),
            fault_source_zh=FAULT_SOURCES_ZH.get(data.profile if data else "", "CiA 402"),
            pt_speed_limit=SpeedLimit(rpm=rpm, source=source),
        )

    async def state(self, node: int) -> DriveState:
        """The drive now: statusword bit by bit, state, mode, position, velocity, torque…"""
        return self.build(node, await self.snapshot(node))

    def unreadable_state(self, node: int) -> DriveState:
        """The last reading (or an empty one) when the drive does not answer."""
        axis = self._drive.axis(node)
        snap = axis.last or Snapshot(0, None, None, None, None, None, None, None, None, None, {})
        return self.build(node, snap)

    # ------------------------------------------------------------------ waiting, explaining

    async def wait(
        self, node: int, done: Callable[[int], bool], timeout: float
    ) -> tuple[bool, int]:
        """Poll 6041h until `done(statusword)`; (reached, last statusword)."""
        deadline = time.monotonic() + timeout
        while True:
            sw = await self._drive.statusword(node)
            if done(sw) or time.monotonic() >= deadline:
                self._drive.axis(node).saw(state_of(sw))
                return done(sw), sw
            await asyncio.sleep(self._drive.settings.motion_poll_interval)

    async def blocked(
        self,
        node: int,
        *,
        extra: list[EnableReason] | None = None,
        target: Cia402State = Cia402State.OPERATION_ENABLED,
        goal: str = "enable",
    ) -> EnableBlockedError:
        """The error for a transition that did not happen, with what the drive shows."""
        nmt = self.nmt(node)
        try:
            snap: Snapshot | None = await self.snapshot(node)
        except (CommTimeoutError, NodeStoppedError):
            snap = None
        axis = self._drive.axis(node)
        data = self._drive.registry.profile_data(node)
        supported = (
            frozenset(int(m) for m in supported_modes(axis.statics.supported_raw))
            if axis.statics and axis.statics.supported_raw is not None
            else None
        )
        state = self.build(node, snap) if snap else self.unreadable_state(node)
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

    async def require_enabled(self, node: int) -> None:
        """Operation enabled, as a TPDO's statusword shows it, else as 6041h read now."""
        given, _ = self._drive.carried(node)
        statusword = given.get("statusword")
        if statusword is None:
            statusword = await self._drive.statusword(node)
        if state_of(statusword) is not Cia402State.OPERATION_ENABLED:
            raise await self.blocked(
                node,
                extra=[reason("not_enabled", "reason.not_enabled")],
            )

    # ------------------------------------------------------------------ modes

    async def set_mode(self, node: int, mode: OperationMode) -> None:
        """Write 6060h and wait until 6061h shows it; an unsupported mode raises
        EnableBlockedError(mode_unsupported) — SDO abort on Kinco/CiA 402, 6061h = 0 on MDi."""
        try:
            await self._drive.write(node, MODES_OF_OPERATION, 0, int(mode), io.I8)
        except SdoAbortError as abort:
            if abort.code != INVALID_VALUE:  # 06090030h: an unsupported 6060h
                raise
            refused = reason("mode_unsupported", "reason.mode_refused", **_mode(mode))
            raise await self.blocked(node, extra=[refused]) from abort
        deadline = time.monotonic() + self.transition_timeout(node)
        while True:
            shown = self._drive.carried(node)[0].get("mode_display")  # a TPDO carrying 6061h
            if shown is None:
                shown = await self._drive.run(
                    node, lambda r: io.read(r, MODES_DISPLAY, signed=True), "read 6061h"
                )
                self._drive.axis(node).sdo_values["mode_display"] = (shown, time.monotonic())
            if shown == mode:
                return
            if time.monotonic() >= deadline:
                not_shown = reason(
                    "mode_unsupported", "reason.mode_not_shown", shown=str(shown), **_mode(mode)
                )
                raise await self.blocked(node, extra=[not_shown])
            await asyncio.sleep(self._drive.settings.motion_poll_interval)


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


def _mode(mode: OperationMode) -> dict[str, str | int]:
    return {"key": str(mode_key(int(mode))), "number": int(mode)}
