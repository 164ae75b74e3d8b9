"""Interpolated position (IP, 6060h = 7): a planned path streamed as 60C1h:01 set-points, one
per SYNC, at the interpolation period 60C2h, with the SYNC sent by the tool itself.

The drive takes 60C1h:01 at each SYNC and travels to it during the following period (MDi-S1-C
CANopen manual §3.8), so point k is written just before SYNC k and names where the axis should
be one period later. The stream runs on the node's worker thread in chunks of about 20 ms
(set-point write, SYNC, every few periods a read of 6064h to measure the lag): a priority stop
waits at most one chunk, and a stop cancels the rest. The first chunk switches interpolation on
and sends the first SYNC one period later (the drive counts SYNC lost from the switch, so no
round trip through the event loop comes between them); 60C2h is written before the mode. The
tool's SYNC producer (SyncService) is paused meanwhile (two SYNC sources would double the
drive's clock) and restarted afterwards.

Before anything is sent, a thread sleeping to the stream's deadlines checks that this host
keeps them (motion/ip_timing.py): a host that cannot is refused with 409 sync_unsafe naming the
measured jitter. A stall (the tool not sending SYNC for more than 3 periods) shows as the
drive's own SYNC-lost fault — MDi alarm 62, Kinco 6011h, CiA 402 8700h — which the result
names, with the gap that stalled it among the measured intervals. A stream that stalled,
faulted or was stopped is recorded as failed in the audit log (its answer is still the 200
result).
"""

from __future__ import annotations

import asyncio
import math
from collections import deque

import canopen

from servodesk.audit import Outcome, current_entry
from servodesk.errors import InvalidValueError
from servodesk.models.motion import IpStreamResult
from servodesk.motion import drive_io as io
from servodesk.motion.core import DriveIo, state_of
from servodesk.motion.drive_limits import Limits
from servodesk.motion.errors import LimitError
from servodesk.motion.ip_stream import Stream
from servodesk.motion.ip_timing import SyncTiming, SyncUnsafeError, probe
from servodesk.motion.readings import Readings
from servodesk.motion.reason_texts import reason
from servodesk.motion.trajectory import Trajectory, peak_velocity, setpoints, sync_jitter
from servodesk.network.sync import SyncService
from servodesk.pdo.commands import IP_DATA, RpdoRoutes
from servodesk_protocol.cia402 import (
    CONTROLWORD,
    MODES_OF_OPERATION,
    Cia402State,
    OperationMode,
    make_enable_operation,
)

CHUNK_S = 0.02  # the longest a priority stop waits behind the stream
LAG_SAMPLE_S = 0.01  # read 6064h about this often (each read takes bus time)
SETTLE_PERIODS = 25  # SYNCs holding the end point before interpolation is switched off
IP_EXPONENT_MS = -3  # 60C2h:02: the period in 10^-3 s
SYNC_LOST = frozenset({62, 0x6011, 0x8700})  # MDi alarm 62, Kinco 6011h, CiA 402 8700h


class IpStreams:
    """IP streams, at most one per node: planned, checked, fed chunk by chunk, judged."""

    def __init__(
        self,
        drive: DriveIo,
        readings: Readings,
        limits: Limits,
        *,
        sync: SyncService | None = None,
        routes: RpdoRoutes | None = None,
    ) -> None:
        self._drive, self._readings, self._limits = drive, readings, limits
        self._sync = sync  # the tool's SYNC producer, paused while a stream runs
        self._routes = routes  # the RPDO that carries 60C1h:01, where there is one
        self._streams: dict[int, Stream] = {}

    async def ip_stream(
        self,
        node: int,
        trajectory: Trajectory,
        *,
        period_ms: int,
        distance_rev: float,
        duration_s: float,
    ) -> IpStreamResult:
        """Stream `trajectory` (a smooth point-to-point move of `distance_rev`, or a sine out
        and back) over `duration_s` at `period_ms`; returns the worst lag, the final error and
        the SYNC jitter. The drives interpolate one point ahead, so the axis runs one period
        behind the plan: on the simulated drives the lag stays within one period of travel at
        the path's peak speed + 0.01 rev (1 rev point-to-point in 1 s: ≤ 0.014 rev at 2 ms,
        ≤ 0.029 rev at 10 ms) and the end within 0.002 rev (tests/backend/test_motion_ip.py).
        Set-points go in the RPDO that maps 60C1h:01 (sent two SYNCs ahead where the drive
        takes it at a SYNC), else by SDO (one expedited write per period); on a busy PC 2 ms
        is at the edge: a stall ends the stream and the result names the drive's SYNC-lost
        fault."""
        if not 1 <= period_ms <= 20:
            raise InvalidValueError("the interpolation period must be 1–20 ms (60C2h)")
        if not 0 < duration_s <= self._drive.settings.motion_ip_max_duration:
            raise InvalidValueError(
                f"the stream lasts 0–{self._drive.settings.motion_ip_max_duration:g} s, "
                f"not {duration_s:g}"
            )
        units = self._drive.units(node)
        axis = self._drive.axis(node)
        peak_rpm = peak_velocity(trajectory, duration_s, distance_rev) * 60
        if peak_rpm > axis.limits.max_velocity_rpm:
            raise LimitError(
                node,
                "error.path_too_fast",
                rpm=f"{peak_rpm:.0f}",
                limit=f"{axis.limits.max_velocity_rpm:g}",
            )
        # off the node's worker thread, which a priority stop must find free: the same host
        timing = await asyncio.to_thread(probe, period_ms / 1000)
        if timing.unsafe:
            raise SyncUnsafeError(node, timing)
        axis.cancel_queue()
        axis.move = None
        await self._readings.require_enabled(node)
        snap = axis.last
        start = snap.position if snap and snap.position is not None else 0
        for end_rev in (units.user_to_rev(start), units.user_to_rev(start) + distance_rev):
            self._limits.check_travel(node, end_rev)
        period = period_ms / 1000
        plan = setpoints(trajectory, start, units.rev_to_user(distance_rev), duration_s, period)
        plan += [plan[-1]] * SETTLE_PERIODS
        # the period first: a drive may take 60C2h when it enters IP mode (the simulated ones
        # do), and one still on an earlier period counts SYNC lost by that one
        await self._drive.write(node, io.IP_PERIOD, 1, period_ms, io.U8)
        await self._drive.write(node, io.IP_PERIOD, 2, IP_EXPONENT_MS, io.I8)
        await self._readings.set_mode(node, OperationMode.INTERPOLATED_POSITION)
        await self._drive.write(node, io.IP_DATA, 1, start, io.I32)
        paused = await self._pause_sync()
        stream = Stream(plan, period)
        self._route_stream(node, stream)
        self._streams[node] = stream
        try:
            word = make_enable_operation(new_setpoint=True)
            await self._feed(node, stream, word, self._readings.transition_timeout(node))
            if stream.not_started:
                raise await self._readings.blocked(
                    node,
                    extra=[reason("timeout", "reason.ip_not_started")],
                )
        finally:
            self._streams.pop(node, None)
            await self._end_stream(node, paused, stream)
        result = await self._result(node, trajectory, period_ms, duration_s, stream, plan, timing)
        entry = current_entry()
        if entry is not None and (result.stalled or result.fault or stream.cancelled):
            entry.report(Outcome("failed", None, "ip_stream_failed", result.message))
        return result

    async def _feed(self, node: int, stream: Stream, controlword: int, timeout: float) -> None:
        """The chunks, two queued at a time so the worker never waits for the event loop
        between them; a priority stop still runs between two chunks. The first chunk switches
        interpolation on (`controlword`) just before its first SYNC."""
        per_chunk = max(1, math.floor(CHUNK_S / stream.period))
        sample_every = max(1, math.ceil(LAG_SAMPLE_S / stream.period))
        chunks = math.ceil(len(stream.points) / per_chunk)

        def first(remote: canopen.RemoteNode) -> None:
            stream.begin(remote, controlword, timeout)
            stream.chunk(remote, per_chunk, sample_every)

        inflight: deque[asyncio.Future[None]] = deque()
        try:
            for index in range(chunks):
                if stream.cancelled or stream.stalled:
                    break
                step = first if index == 0 else lambda r: stream.chunk(r, per_chunk, sample_every)
                # in the normal lane: a stream keeps its next chunk queued, and commands must
                # not starve the node's other requests (nodes/session.py)
                call = self._drive.run(node, step, "IP", command=False)
                inflight.append(asyncio.ensure_future(call))
                if len(inflight) > 1:
                    await inflight.popleft()
            while inflight:
                await inflight.popleft()
        finally:
            stream.cancelled = stream.cancelled or stream.sent < len(stream.points)
            for pending in inflight:
                pending.cancel()

    def _route_stream(self, node: int, stream: Stream) -> None:
        """Set-points in the RPDO that maps 60C1h:01 where the drive has one (its other objects
        known: the stream's controlword, 6060h = 7), else by SDO."""
        found = self._routes.ip_route(node) if self._routes is not None else None
        if found is None:
            return
        stream.rpdo, synchronous = found
        stream.lead = 2 if synchronous else 1
        ip_mode = int(OperationMode.INTERPOLATED_POSITION)
        stream.rpdo_values = {MODES_OF_OPERATION: ip_mode, IP_DATA: 0}

    async def _end_stream(self, node: int, paused: int | None, stream: Stream) -> None:
        try:
            state = state_of(await self._drive.statusword(node))
            if state is Cia402State.OPERATION_ENABLED:
                await self._drive.controlword(node, make_enable_operation())  # interpolation off
            if stream.rpdo is not None:
                await self._settle_rpdo(node, stream)
        finally:
            if paused is not None and self._sync is not None:
                await self._sync.set(paused)

    async def _result(
        self,
        node: int,
        trajectory: Trajectory,
        period_ms: int,
        duration_s: float,
        stream: Stream,
        plan: list[int],
        timing: SyncTiming,
    ) -> IpStreamResult:
        units = self._drive.units(node)
        state = await self._readings.state(node)
        actual = units.inc_to_user(state.position_inc)
        final_error = units.user_to_inc(abs(actual - plan[-1]))
        jitter, longest = sync_jitter(stream.syncs, stream.period)
        if stream.stalled:  # the gap that stalled it is an interval too (its SYNC never went)
            longest = max(longest, stream.stall_gap)
            jitter = max(jitter, stream.stall_gap - stream.period)
        max_lag = units.user_to_inc(max(stream.lags, default=0))
        stalled_by_tool = stream.stalled or longest > 3 * stream.period
        stalled = stalled_by_tool or state.fault is not None
        words = [f"{stream.sent} set-points at {period_ms} ms"]
        if state.fault is not None:
            words.append(
                f"the drive faulted: {state.fault.code_hex} {state.fault.name or ''}".strip()
            )
        elif stream.cancelled:
            words.append("stopped before its end")
        if stream.stalled:
            words.append(
                f"the stream stalled: no SYNC for {stream.stall_gap * 1000:.2f} ms, more than "
                f"3 periods ({3 * period_ms} ms); this computer was too busy to keep time"
            )
        elif state.fault is not None and state.fault.code in SYNC_LOST and not stalled_by_tool:
            words.append(
                f"the tool's SYNC intervals stayed within {longest * 1000:.2f} ms: the drive "
                "or the bus took them late"
            )
        if timing.marginal and stalled:
            words.append(f"the check before the stream measured {timing.words()}")
        elif timing.marginal:
            words.append(f"SYNC timing was marginal before the stream ({timing.words()})")
        return IpStreamResult(
            node=node,
            trajectory=trajectory,
            period_ms=period_ms,
            points=stream.sent,
            syncs=len(stream.syncs),
            duration_s=duration_s,
            max_lag_inc=max_lag,
            max_lag_rev=units.inc_to_rev(max_lag),
            final_error_inc=final_error,
            sync_jitter_ms=jitter * 1000,
            sync_interval_max_ms=longest * 1000,
            stalled=stalled,
            fault=state.fault,
            message="; ".join(words),
            state=state,
        )

    async def _settle_rpdo(self, node: int, stream: Stream) -> None:
        """The drive holds the stream's last RPDO until the next SYNC, which would apply its
        controlword (interpolation on) after the stream ended or a stop: send it once more with
        the controlword the drive holds now, before any SYNC (the tool's is still paused)."""

        def settle(remote: canopen.RemoteNode) -> None:
            word = io.read(remote, CONTROLWORD, signed=False)
            if word is not None:
                stream.rpdo_values[CONTROLWORD] = word
                stream.send_rpdo(remote)

        await self._drive.registry.session(node).priority(settle, what=f"settle node {node}'s RPDO")

    def stream_points_sent(self, node: int) -> int | None:
        """How many set-points the running stream of `node` has sent; None when none runs."""
        stream = self._streams.get(node)
        return None if stream is None else stream.sent

    def cancel_stream(self, node: int) -> None:
        """Stop feeding set-points (the stop paths call it; the drive then holds or faults)."""
        stream = self._streams.get(node)
        if stream is not None:
            stream.cancelled = True

    async def _pause_sync(self) -> int | None:
        """Stop the tool's SYNC producer for the stream; the period to restart it with."""
        if self._sync is None:
            return None
        config = self._sync.get()
        if not config.producing or not config.period_us:
            return None
        await self._sync.set(None)
        return config.period_us
