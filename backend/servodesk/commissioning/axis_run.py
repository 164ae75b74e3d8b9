"""What the moving steps (stop_test, test_move) share: the axis taken as ServoDesk's own client
and always given back stopped and disabled, scope captures around the motion, keep-alives for
the step's own jogs, and waits on the drive's readings (no fixed sleeps: each wait ends on what
the drive or the capture shows, within a bound).

Everything goes through the project's motion safety layer and scope service: the lease, the
jog watchdog, the stop paths on the node's priority lane, the scope's plan and setup."""

from __future__ import annotations

import asyncio
import contextlib
import logging
import time
import uuid
from collections.abc import AsyncIterator, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from servodesk.audit import AuditLog
from servodesk.commissioning.evidence import step_audit_ids
from servodesk.commissioning.stop_figures import Series
from servodesk.errors import ServodeskError
from servodesk.models.safety import JogInfo
from servodesk.models.scope import Capture, CaptureRequest, ScopeSignalRequest
from servodesk.motion.jog import JogStoppedError
from servodesk.motion.lease import Client
from servodesk.motion.safety import MotionSafety
from servodesk.motion.stop_reasons import Reason
from servodesk.nodes.access import NodeAccess
from servodesk.scope.samples import read_samples
from servodesk.scope.service import ScopeService
from servodesk.sdo.service import SdoService
from servodesk.settings import Settings

log = logging.getLogger(__name__)

VELOCITY_ACTUAL = 0x606C  # Velocity actual value
POSITION_ACTUAL = 0x6064  # Position actual value
FOLLOWING_ERROR = 0x60F4  # Following error actual value
# SYNC periods tried in order: the finest the bus load allows (the scope's plan says)
SYNC_PERIODS_US = (2000, 4000, 10000, 20000)
CAPTURE_LIMIT_S = 120.0  # a capture's own end, should the step never stop it
POLL_S = 0.02  # readings while waiting on the drive
ARM_WAIT_S = 15.0  # the scope's setup (TPDOs, SYNC, NMT) on a busy PC
SAMPLES_AFTER = 20  # samples of each signal recorded after the axis is at rest


class StepError(ServodeskError):
    """The moving step cannot go on; the step is recorded failed with this."""


@dataclass
class AxisRun:
    """One moving step on one node: its tools, its client, what it found."""

    safety: MotionSafety
    scope: ScopeService
    access: NodeAccess
    sdo: SdoService
    audit: AuditLog
    settings: Settings
    node: int
    client: Client
    started: float = field(default_factory=time.time)
    found_state: str | None = None
    found_mode: str | None = None
    captures: list[int] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    @property
    def rest_rpm(self) -> float:
        return self.settings.jog_rest_rpm

    # ------------------------------------------------------------------ control

    @contextlib.asynccontextmanager
    async def controlled(self) -> AsyncIterator[AxisRun]:
        """Take the axis (409 held_by_other when a page holds it); whatever happens, leave it
        stopped, disabled and released, in the mode it was found in."""
        found = await self.safety.motion.state(self.node)
        self.found_state, self.found_mode = found.state, found.mode
        await self.safety.take(self.node, self.client, take_over=False)
        try:
            yield self
        finally:
            await self._give_back()

    async def _give_back(self) -> None:
        safety, node = self.safety, self.node
        for capture_id in self.captures:  # a capture the step did not get to end
            await self._attempt("end the capture", self.scope.stop(capture_id))
        safety.jogs.stop_node(node, Reason("stop.step_ended"), by_tool=True)
        with contextlib.suppress(ServodeskError):
            if abs(await safety.motion.velocity_rpm(node)) >= self.rest_rpm:
                await safety.quick_stop(node)
                await self.wait_rest(10.0)
        await self._attempt("disable", safety.motion.disable(node))
        mode = self.found_mode
        if mode is not None and mode != (await safety.motion.state(node)).mode:
            await self._attempt(f"mode back to {mode}", safety.motion.set_mode(node, mode))
        await self._attempt("release", safety.release(node, self.client))

    async def _attempt(self, what: str, step: Any) -> None:
        try:
            await step
        except ServodeskError as error:
            log.warning("node %d: commissioning: %s failed: %s", self.node, what, error)
            self.notes.append(f"{what} failed: {error}")

    # ------------------------------------------------------------------ waits

    async def wait_steady(self, rpm: float, timeout: float) -> float:
        """Until 606Ch holds `rpm` (within 2 % or the rest threshold) for 3 readings; the last
        reading. StepError when it does not within `timeout`."""
        loop = asyncio.get_running_loop()
        deadline = loop.time() + timeout
        tolerance = max(abs(rpm) * 0.02, self.rest_rpm)
        steady = 0
        reading = 0.0
        while loop.time() < deadline:
            reading = await self.safety.motion.velocity_rpm(self.node)
            steady = steady + 1 if abs(reading - rpm) <= tolerance else 0
            if steady >= 3:
                return reading
            await asyncio.sleep(POLL_S)
        raise StepError(
            f"node {self.node}: the jog did not settle at {rpm:g} rpm within {timeout:g} s "
            f"(606Ch: {reading:.1f} rpm)"
        )

    async def wait_rest(self, timeout: float) -> bool:
        """Until two readings of 606Ch below the rest threshold; False when not in `timeout`."""
        loop = asyncio.get_running_loop()
        deadline = loop.time() + timeout
        still = 0
        while loop.time() < deadline:
            rpm = await self.safety.motion.velocity_rpm(self.node)
            still = still + 1 if abs(rpm) < self.rest_rpm else 0
            if still >= 2:
                return True
            await asyncio.sleep(POLL_S)
        return False

    async def wait_jog_stopped(self, jog_id: str, timeout: float) -> JogInfo:
        """Until the jog watchdog says the jog's axis is at rest ("stopped")."""
        loop = asyncio.get_running_loop()
        deadline = loop.time() + timeout
        info = self.safety.jogs.get(jog_id)
        while info.state != "stopped" and loop.time() < deadline:
            await asyncio.sleep(POLL_S)
            info = self.safety.jogs.get(jog_id)
        return info

    # ------------------------------------------------------------------ keep-alives

    @contextlib.asynccontextmanager
    async def keepalives(self, jog: JogInfo) -> AsyncIterator[list[float]]:
        """Keep the step's jog alive (as a held button does) until the block ends; yields the
        list whose last item is the time (epoch s) of the last keep-alive sent."""
        sent = [time.time()]  # starting the jog armed its timer
        stop = asyncio.Event()

        async def beat() -> None:
            interval = jog.keepalive_ms / 1000 / 4
            while not stop.is_set():
                try:
                    self.safety.keepalive(jog.jog_id, self.client)
                except JogStoppedError:
                    return
                sent.append(time.time())
                with contextlib.suppress(TimeoutError):
                    await asyncio.wait_for(stop.wait(), interval)

        task = asyncio.create_task(beat(), name=f"commissioning keep-alive node {self.node}")
        try:
            yield sent
        finally:
            stop.set()
            await task

    # ------------------------------------------------------------------ captures

    async def start_capture(self, name: str, indices: Sequence[int]) -> Capture:
        """A free-running capture of the node's `indices` (those its dictionary has) at the
        finest SYNC period the bus load allows; returns once it records (state running)."""
        od = self.access.od(self.node)
        signals = [
            ScopeSignalRequest(node=self.node, index=i, subindex=0)
            for i in indices
            if od.get(i, 0) is not None
        ]
        request = None
        for period in SYNC_PERIODS_US:
            candidate = CaptureRequest(
                signals=signals, sync_period_us=period, duration_s=CAPTURE_LIMIT_S, name=name
            )
            if (await self.scope.plan(candidate)).ok:
                request = candidate
                break
        if request is None:
            raise StepError(
                f"node {self.node}: no SYNC period up to {SYNC_PERIODS_US[-1]} µs fits the bus "
                "load for the capture: see the Scope page's plan"
            )
        capture = await self.scope.start(request)
        self.captures.append(capture.id)
        loop = asyncio.get_running_loop()
        deadline = loop.time() + ARM_WAIT_S
        while loop.time() < deadline:
            capture = await self.scope.get(capture.id)
            if capture.state in ("done", "failed"):
                raise StepError(f"capture {capture.id} ended before the test: {capture.error}")
            if capture.state in ("armed", "running") and capture.samples > 0:
                return capture
            await asyncio.sleep(POLL_S)
        raise StepError(f"capture {capture.id} did not start recording within {ARM_WAIT_S:g} s")

    async def end_capture(self, capture_id: int) -> tuple[Capture, dict[int, Series]]:
        """Record a little more (the rest after the motion), stop the capture and read its
        samples by object index."""
        capture = await self.scope.get(capture_id)
        wanted = capture.samples + SAMPLES_AFTER * max(1, len(capture.signals))
        loop = asyncio.get_running_loop()
        deadline = loop.time() + 5.0
        while capture.samples < wanted and capture.state == "running":
            if loop.time() > deadline:
                break
            await asyncio.sleep(POLL_S)
            capture = await self.scope.get(capture_id)
        stopped = await self.scope.stop(capture_id)
        self.captures.remove(capture_id)
        capture = stopped or await self.scope.get(capture_id)
        if capture.state == "failed":
            raise StepError(f"capture {capture_id} failed: {capture.error}")
        path = self.scope.store.samples_path(capture_id)
        series = await asyncio.to_thread(_read_series, path, capture)
        return capture, series

    # ------------------------------------------------------------------ evidence

    async def audit_ids(self) -> list[int]:
        return await step_audit_ids(self.audit, self.node, self.started)


def _read_series(path: Any, capture: Capture) -> dict[int, Series]:
    """The node's signals of a finished capture by object index: (timestamp, value) in time
    order."""
    times: dict[int, list[np.ndarray[Any, Any]]] = {}
    values: dict[int, list[np.ndarray[Any, Any]]] = {}
    for batch in read_samples(path, columns=("signal", "timestamp", "value")):
        signal = batch.column(0).to_numpy()
        stamp = batch.column(1).to_numpy()
        value = batch.column(2).to_numpy()
        for position in np.unique(signal):
            index = capture.signals[int(position)].index
            rows = signal == position
            times.setdefault(index, []).append(stamp[rows])
            values.setdefault(index, []).append(value[rows])
    out: dict[int, Series] = {}
    for index, parts in times.items():
        t = np.concatenate(parts)
        v = np.concatenate(values[index])
        order = np.argsort(t, kind="stable")
        out[index] = Series(t[order].astype(np.float64), v[order].astype(np.float64))
    return out


def app_client(step: str, record_id: int) -> Client:
    """ServoDesk's own client for the step: a page cannot mistake it for one of its own."""
    return Client(
        id=f"commissioning-{record_id}-{uuid.uuid4().hex[:8]}",
        name=f"commissioning record {record_id}: {step}",
    )
