"""The scope service: plan a capture (planner.py), set the bus up for it and put it back
(bus_setup.py), record it, keep the captures and export them.

One capture series runs at a time. Its setup (the TPDOs the scope mapped, the SYNC period, the
nodes it started) is made once and undone when the series ends; in `normal` trigger mode the
series re-arms a new capture after each one and keeps the last `keep`.
"""

from __future__ import annotations

import asyncio
import logging
import time
import uuid
from collections.abc import Callable, Sequence
from pathlib import Path

from servodesk.bus.connection import BusManager
from servodesk.errors import InvalidValueError, ServodeskError, StateConflictError
from servodesk.events.bus import EventBus
from servodesk.models.scope import (
    ACTIVE_STATES,
    Capture,
    CaptureRequest,
    CaptureState,
    ExportFormat,
    ExportLayout,
    ScopePlan,
)
from servodesk.network.sync import SyncService
from servodesk.nodes.access import NodeAccess
from servodesk.pdo.service import PdoService
from servodesk.scope import export as exports
from servodesk.scope import retention
from servodesk.scope.bus_setup import BusSetup
from servodesk.scope.checks import SilentSignalsError, overload
from servodesk.scope.frames import FrameSink
from servodesk.scope.planner import MAX_LOAD_PERCENT, ScopePlanner, Setup
from servodesk.scope.recording import CaptureRecording
from servodesk.scope.run import (
    FLUSH_S,
    CaptureOutput,
    CaptureRun,
    close_files,
    poll_sdo,
)
from servodesk.scope.samples import SamplesWriter
from servodesk.scope.setup import build_core
from servodesk.scope.store import CaptureStore
from servodesk.scope.viewer_server import RerunServer
from servodesk.storage.usage import UsageMeter

log = logging.getLogger(__name__)

ROOM_CHECK_S = 1.0  # how often a recording capture checks its size and the disk's free space
TEARDOWN_WAIT_S = 10.0  # a new capture waits this long for the last one's setup to be undone


class ScopeService:
    def __init__(
        self,
        access: NodeAccess,
        pdos: PdoService,
        sync: SyncService,
        bus: BusManager,
        events: EventBus,
        store: CaptureStore,
        viewer: RerunServer | None,
        *,
        known_nodes: Callable[[], Sequence[int]],
        usage: UsageMeter | None = None,
    ) -> None:
        self.known_nodes = known_nodes
        self.usage = usage  # its quotas keep captures within bounds (scope/retention.py)
        self.access = access
        self.pdos = pdos
        self.sync = sync
        self.bus = bus
        self.events = events
        self.store = store
        self.viewer = viewer
        self.planner = ScopePlanner(access, pdos, known_nodes)
        self.bus_setup = BusSetup(access, pdos, sync)
        self._lock = asyncio.Lock()
        self._setup: Setup | None = None
        self._run: CaptureRun | None = None
        self._series_task: asyncio.Task[None] | None = None
        self._arming: int | None = None  # the capture whose bus setup `start` is doing

    async def open(self) -> None:
        await asyncio.to_thread(self.store.open)
        if self.usage is not None:
            await asyncio.to_thread(retention.prune, self.store, self.usage.captures_keep)

    # ------------------------------------------------------------------ planning

    async def plan(self, request: CaptureRequest) -> ScopePlan:
        return await self.planner.plan(request)

    # ------------------------------------------------------------------ starting and stopping

    async def start(self, request: CaptureRequest) -> Capture:
        async with self._lock:
            task = self._series_task
            if self._setup is not None and self._run is None and task is not None:
                # the last capture is done and the bus is being put back: wait for that
                await asyncio.wait({task}, timeout=TEARDOWN_WAIT_S)
            if self._setup is not None:
                busy = self._run.capture.id if self._run else "(being put back)"
                raise StateConflictError(
                    "scope_busy",
                    f"capture {busy} is still armed or running: stop it"
                    f" (DELETE /api/scope/captures/{busy}) before starting another",
                )
            setup = await self.planner.prepare(request)
            if setup.bus_load_percent > MAX_LOAD_PERCENT:
                raise InvalidValueError(overload(setup.bus_load_percent, request.sync_period_us))
            # the record first: while the bus is set up it is listed as `arming`
            capture = await self._create(setup)
            self._arming = capture.id
            try:
                await self.bus_setup.configure(setup)
                run = await self._begin(setup, capture)
            except BaseException:
                await self.bus_setup.undo(setup)
                await self._forget_capture(capture.id)  # nothing was recorded
                raise
            finally:
                self._arming = None
            self._setup = setup
            self._series_task = asyncio.create_task(self._series(setup, run))
            return run.capture.model_copy(deep=True)

    async def _create(self, setup: Setup, series: int | None = None) -> Capture:
        """The capture's record, `arming` until its trigger can fire (run.py `refresh`)."""
        request = setup.request

        def build(capture_id: int) -> Capture:
            return Capture(
                id=capture_id,
                name=request.name,
                state="arming",
                created=time.time(),
                started=time.time(),
                signals=[s.model_copy(deep=True) for s in setup.signals],
                nodes=sorted(setup.plans),
                sync_period_us=request.sync_period_us,
                duration_s=request.duration_s,
                trigger=request.trigger,
                lanes=request.lanes,
                samples=0,
                bus_load_percent=round(setup.bus_load_percent, 1),
                recording_id=str(uuid.uuid4()),
                series=series,
                notes=list(setup.notes),
            )

        return await asyncio.to_thread(self.store.create, build)

    async def _forget_capture(self, capture_id: int) -> None:
        try:
            await asyncio.to_thread(self.store.delete, capture_id)
        except ServodeskError as error:
            log.warning("scope: could not delete capture %s: %s", capture_id, error)

    async def _begin(self, setup: Setup, capture: Capture) -> CaptureRun:
        """Recording starts on the configured bus: the capture's files, tap and pollers."""
        request = setup.request
        capture.notes = list(setup.notes)  # with what setting the bus up noted
        capture.started = time.time()
        live = await self._live_url(capture)
        rrd = self.store.rrd_path(capture.id)
        recording = await asyncio.to_thread(CaptureRecording, capture, rrd, live)
        writer = SamplesWriter(self.store.samples_path(capture.id))
        output = CaptureOutput(capture, writer, recording)
        scope_pdos = {node: plan.scope_pdos for node, plan in setup.plans.items()}
        core = build_core(capture.signals, setup.infos, scope_pdos, request, output)
        sink = FrameSink([cob for cob in core.streams if cob < 0x800])
        run = CaptureRun(capture, core, sink, output)
        run.cleanups.append(self.bus.add_frame_listener(sink))
        run.cleanups.append(self.events.subscribe(run.on_event))
        period = request.sync_period_us / 1e6
        for node in capture.nodes:
            polled = [
                (i, s.node, s.index, s.subindex)
                for i, s in enumerate(capture.signals)
                if s.source == "sdo" and s.node == node
            ]
            if polled:
                task = asyncio.create_task(
                    poll_sdo(self.access, sink, polled, period, capture.notes)
                )
                run.pollers.append(task)
        self._run = run
        return run

    async def _live_url(self, capture: Capture) -> str | None:
        if self.viewer is None:
            return None
        try:
            await self.viewer.ensure_started()
        except ServodeskError as error:
            capture.notes.append(f"live view unavailable ({error}); the capture is recorded")
            return None
        return self.viewer.grpc_url

    async def _series(self, setup: Setup, run: CaptureRun) -> None:
        """Record captures until the series ends, then undo the setup."""
        try:
            while True:
                await self._record(run)
                self._keep(setup, run.capture)
                await self._prune(run.capture)
                again = (
                    setup.request.trigger.mode == "normal"
                    and run.stop_reason is None
                    and run.capture.state == "done"
                )
                if not again:
                    break
                setup.series = setup.series or run.capture.id
                if run.capture.series is None:
                    run.capture.series = setup.series
                    await asyncio.to_thread(self.store.save, run.capture)
                run = await self._begin(setup, await self._create(setup, setup.series))
        finally:
            self._run = None
            await self.bus_setup.undo(setup)
            self._setup = None

    async def _record(self, run: CaptureRun) -> None:
        capture = run.capture
        final: CaptureState = "done"  # set once the files are closed: done means exportable
        try:
            saved_state = capture.state
            room_check = time.monotonic() + ROOM_CHECK_S
            while run.stop_reason is None:
                await asyncio.sleep(FLUSH_S)
                await run.flush()
                if time.monotonic() >= room_check:
                    room_check = time.monotonic() + ROOM_CHECK_S
                    no_room = await self._no_room(capture.id)
                    if no_room is not None:
                        capture.notes.append(no_room)
                        break
                if capture.state != saved_state:
                    saved_state = capture.state
                    await asyncio.to_thread(self.store.save, capture.model_copy(deep=True))
                if run.core.done():
                    break
                silent = run.silent(time.time())
                if silent:
                    raise SilentSignalsError(silent, self._nmt_states(capture.nodes))
                if run.stalled(time.time()):
                    capture.notes.append(
                        "ended early: no samples for 2 s (a drive stopped sending: NMT state,"
                        " SYNC or bus)"
                    )
                    break
            await run.flush()  # what arrived until now
            if run.stop_reason is not None:
                capture.notes.append(run.stop_reason)
        except SilentSignalsError as error:
            final = "failed"
            capture.error = str(error)
        except Exception as error:  # the capture fails, the series ends, the bus is restored
            log.exception("capture %s failed", capture.id)
            final = "failed"
            capture.error = f"{type(error).__name__}: {error}"
        finally:
            for cleanup in run.cleanups:
                cleanup()
            for task in run.pollers:
                task.cancel()
            await asyncio.gather(*run.pollers, return_exceptions=True)
            await asyncio.to_thread(close_files, run)
            if run.core.short_frames:
                capture.notes.append(
                    f"{run.core.short_frames} frame(s) shorter than the scope's mapping skipped"
                )
            capture.ended = time.time()
            capture.size_bytes = await asyncio.to_thread(self.store.size_bytes, capture.id)
            capture.state = final
            await asyncio.to_thread(self.store.save, capture.model_copy(deep=True))

    async def _no_room(self, capture_id: int) -> str | None:
        usage = self.usage
        if usage is None:
            return None
        return await asyncio.to_thread(
            retention.room_left, self.store, capture_id, usage.captures_keep, usage.min_free
        )

    async def _prune(self, capture: Capture) -> None:
        """Keep captures within their quota; the one just ended stays and notes what went."""
        if self.usage is None:
            return
        keep = self.usage.captures_keep
        removed = await asyncio.to_thread(retention.prune, self.store, keep, {capture.id})
        self.usage.forget()
        if removed:
            capture.notes.append(retention.pruned_note(removed, keep))
            await asyncio.to_thread(self.store.save, capture.model_copy(deep=True))

    def _nmt_states(self, nodes: Sequence[int]) -> dict[int, str]:
        states: dict[int, str] = {}
        for node in nodes:
            try:
                states[node] = self.access.info(node).nmt_state.value
            except ServodeskError:
                states[node] = "not on the bus"
        return states

    def _keep(self, setup: Setup, capture: Capture) -> None:
        if setup.request.trigger.mode != "normal":
            return
        setup.kept.append(capture.id)
        while len(setup.kept) > setup.request.trigger.keep:
            old = setup.kept.pop(0)
            try:
                self.store.delete(old)
            except ServodeskError as error:
                log.warning("scope: could not delete capture %s: %s", old, error)

    async def stop(self, capture_id: int) -> Capture | None:
        """Stop the capture if it is the one recording (returns it, its state final); None
        when it is not active."""
        if capture_id == self._arming:
            async with self._lock:  # its setup finishes (or fails) first
                pass
        run = self._run
        if run is None or run.capture.id != capture_id:
            return None
        run.stop("stopped by the user")
        task = self._series_task
        if task is not None:
            await asyncio.shield(task)
        return await self.get(capture_id)

    # ------------------------------------------------------------------ captures

    async def list(self) -> list[Capture]:
        captures = await asyncio.to_thread(self.store.list)
        run = self._run
        if run is not None:
            captures = [run.capture if c.id == run.capture.id else c for c in captures]
        return [c.model_copy(deep=True) for c in captures]

    async def get(self, capture_id: int) -> Capture:
        run = self._run
        if run is not None and run.capture.id == capture_id:
            return run.capture.model_copy(deep=True)
        return await asyncio.to_thread(self.store.get, capture_id)

    async def delete(self, capture_id: int) -> None:
        await asyncio.to_thread(self.store.delete, capture_id)

    async def export(
        self, capture_id: int, fmt: ExportFormat, layout: ExportLayout = "long"
    ) -> Path:
        capture = await self.get(capture_id)
        if capture.state in ACTIVE_STATES:
            raise StateConflictError(
                "capture_recording",
                f"capture {capture_id} is still {capture.state}: export it when it is done"
                " (or stop it)",
            )
        if layout == "wide" and fmt != "csv":
            raise InvalidValueError(f"the wide layout is for CSV only, not {fmt}: leave it out")
        if fmt == "rrd":
            return self.store.rrd_path(capture_id)
        samples = self.store.samples_path(capture_id)
        out = self.store.directory(capture_id) / exports.filename(capture, fmt, layout)
        return await asyncio.to_thread(exports.export, capture, samples, fmt, out, layout)

    async def close(self) -> None:
        run = self._run
        if run is not None:
            run.stop("stopped: ServoDesk is shutting down")
        task = self._series_task
        if task is not None and not task.done():
            await asyncio.gather(task, return_exceptions=True)
        await asyncio.to_thread(self.store.close)
