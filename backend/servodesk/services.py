"""The services of one running app, built together and owned by the app's lifespan (no global
singletons for live state: tests build as many independent apps as they like)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

from servodesk.audit import AuditLog, Outcome
from servodesk.audit.log import Describe
from servodesk.bus.connection import BusFactory, BusManager
from servodesk.commissioning import CommissioningService
from servodesk.events.bus import EventBus
from servodesk.faults.collector import collect, quiet_short_emcy
from servodesk.faults.service import FaultService
from servodesk.live import LiveHub
from servodesk.logs.recording import Recorder
from servodesk.logs.service import LogService
from servodesk.loop_watch import LoopWatch
from servodesk.motion.publish import jog_stopped
from servodesk.motion.safety import MotionSafety
from servodesk.motion.service import MotionService
from servodesk.network.sync import SyncService
from servodesk.nodes.registry import NodeRegistry
from servodesk.od.parser import OdParser
from servodesk.params.node_id import NodeIdService
from servodesk.params.paramsets import ParamSetService
from servodesk.params.service import ParamService
from servodesk.pdo.publish import pdo_applied
from servodesk.pdo.service import PdoService
from servodesk.pdo.write_watch import SdoWriteWatch
from servodesk.scope.service import ScopeService
from servodesk.scope.store import CaptureStore
from servodesk.scope.viewer_server import RerunServer
from servodesk.sdo.jobs import JobManager
from servodesk.sdo.publish import PublishingSdoService
from servodesk.sdo.service import SdoService
from servodesk.settings import Settings
from servodesk.storage import Retention, Storage
from servodesk.storage.usage import UsageMeter


@dataclass
class Services:
    settings: Settings
    bus: BusManager
    registry: NodeRegistry
    sync: SyncService
    sdo: SdoService
    jobs: JobManager
    params: ParamService
    node_ids: NodeIdService
    paramsets: ParamSetService
    pdos: PdoService
    motion: MotionService
    safety: MotionSafety
    live: LiveHub
    od_parser: OdParser
    # faults and field diagnostics (events/, storage/, faults/, logs/)
    events: EventBus
    storage: Storage
    faults: FaultService
    logs: LogService
    recorder: Recorder
    viewer: RerunServer  # the scope's rerun viewer and gRPC server (loopback, lazily started)
    scope: ScopeService
    audit: AuditLog  # every write to a drive: who, when, old → new, result
    loop_watch: LoopWatch  # the event loop's lag (GET /api/health) and its stalls (the log)
    usage: UsageMeter  # what the data directory holds against its quotas (GET /api/health)
    commissioning: CommissioningService  # commissioning records (SQLite beside the timeline)

    async def open(self) -> None:
        """The audit log, the event bus and the timeline store, before the bus connects
        (nothing is missed)."""
        await self.audit.open()
        self.events.attach_loop()
        await self.storage.start()
        await self.scope.open()
        await self.logs.open()

    def start(self) -> None:
        self.loop_watch.start()
        self.safety.start()
        self.live.start()

    async def close(self) -> None:
        self.od_parser.close()
        self.logs.close()
        # first: a running capture puts the bus back (its TPDOs, SYNC, NMT states)
        await self.scope.close()
        await self.recorder.close()
        await self.viewer.close()  # after the scope: its recordings stream into the viewer
        await self.live.close()
        # before the registry and bus go: running jogs are stopped, 1016h entries restored
        await self.safety.close()
        self.motion.close()  # its TPDO subscriptions
        self.pdos.close()
        await self.jobs.close()
        self.sync.close()
        await self.registry.close()
        await self.bus.close()
        self.faults.close()
        self.commissioning.close()
        await self.storage.close()  # what the others published on the way out is kept
        await self.audit.close()  # last: the results of the stops made on the way out
        await self.loop_watch.close()


def build_services(
    settings: Settings,
    *,
    bus_factory: BusFactory | None = None,
    describe_error: Describe = Outcome.of_error,
) -> Services:
    """Every service, wired; `describe_error` gives an error's kind and words for the audit log
    (the app passes the API's own, so tool-made entries read like a request's)."""
    bus = BusManager(settings, bus_factory=bus_factory)
    od_parser = OdParser()  # uploads and the profiles' dictionaries, in worker processes
    events = EventBus()  # the one stream: storage, the timeline, the live channel subscribe
    registry = NodeRegistry(bus, settings, parser=od_parser, events=events)
    jobs = JobManager(registry)
    registry.add_od_listener(jobs.dictionary_changed)
    sync = SyncService(bus)
    storage, faults = _diagnostics(settings, bus, registry)
    pdos = PdoService(
        registry,
        known_nodes=lambda: [info.node for info in registry.all()],
        network=lambda: bus.network,
        bitrate=lambda: bus.status().bitrate,
        sync=sync.get,
        on_applied=lambda node, before, after: pdo_applied(events.publish, node, before, after),
    )
    # the cached PDOs go stale on a dictionary change, NMT command, boot-up, bus change or an
    # SDO write to a PDO parameter (SdoService on_write and the bus watch below; a DCF load
    # tells the service itself)
    registry.add_od_listener(pdos.forget)
    events.subscribe(pdos.on_event)
    bus.add_listener(pdos.on_bus)
    bus.add_frame_listener(pdos.sync_heard)  # SYNC from another producer counts as SYNC
    # a PDO parameter written by anyone (this tool or another master) drops the cached PDOs
    bus.add_frame_listener(SdoWriteWatch(pdos.sdo_written), sent=True)
    motion = MotionService(
        registry, settings, pdos, sync=sync, on_statusword=faults.observe_statusword
    )
    events.subscribe(motion.on_event)  # other writes, resets: what it wrote may have changed
    audit = AuditLog(settings.data_dir, describe=describe_error)
    safety = MotionSafety(motion, bus, registry, settings, record=audit.by_tool)
    safety.jogs.add_listener(partial(jog_stopped, events.publish))
    live = LiveHub(bus, registry, safety)
    # the timeline and the active faults on the WebSocket (subscribed after the store: ids)
    live.follow_diagnostics(events, storage.id_of, faults.add_listener, faults.all_active)
    viewer = RerunServer(settings.data_dir / "rerun")
    params = ParamService(registry, publish=events.publish)
    events.subscribe(params.on_node_event)
    usage = UsageMeter(
        settings.data_dir,
        logs_keep_mb=settings.logs_keep_mb,
        captures_keep_mb=settings.captures_keep_mb,
        min_free_mb=settings.data_min_free_mb,
    )
    scope = ScopeService(
        registry,
        pdos,
        sync,
        bus,
        events,
        CaptureStore(settings.data_dir / "scope"),
        viewer=viewer if settings.scope_live_view else None,
        known_nodes=lambda: [info.node for info in registry.all()],
        usage=usage,
    )
    sdo = PublishingSdoService(registry, bus=events, on_write=pdos.sdo_written)
    return Services(
        settings=settings,
        bus=bus,
        registry=registry,
        sync=sync,
        sdo=sdo,
        jobs=jobs,
        params=params,
        node_ids=NodeIdService(registry, settings),
        paramsets=ParamSetService(registry, od_parser, pdos, publish=events.publish),
        pdos=pdos,
        motion=motion,
        safety=safety,
        live=live,
        od_parser=od_parser,
        events=events,
        storage=storage,
        faults=faults,
        logs=LogService(
            settings.data_dir,
            max_concurrent=settings.log_decodes_max,
            keep_bytes=usage.logs_keep,
        ),
        # a recording holds the whole bus: the frames the tool sends as well as those it hears
        recorder=Recorder(partial(bus.add_frame_listener, sent=True), settings.data_dir),
        viewer=viewer,
        scope=scope,
        audit=audit,
        loop_watch=LoopWatch(),
        usage=usage,
        commissioning=CommissioningService(
            registry,
            sdo,
            params,
            audit,
            settings,
            bitrate=lambda: bus.status().bitrate,
            simulated=lambda: bus.status().simulated,
            safety=safety,
            scope=scope,
            pdos=pdos,
        ),
    )


def _diagnostics(
    settings: Settings, bus: BusManager, registry: NodeRegistry
) -> tuple[Storage, FaultService]:
    """The event bus's timeline store and the fault service, wired (docs/architecture.md,
        "Faults and the timeline"). The live channel subscribes with `events.subscribe` after the
    store (LiveHub.follow_diagnostics), so it can tell each event's timeline id."""
    events = registry.events
    retention = Retention(
        settings.events_max_rows, settings.events_max_days, settings.faults_max_rows
    )
    storage = Storage(settings.data_dir, retention, bus_of=bus.label)
    faults = FaultService(registry, events, storage, settings)
    events.subscribe(storage.add_event)
    collect(bus.frames, events, faults.on_emcy)  # EMCYs and SDO aborts, from the bus's tap
    quiet_short_emcy()  # canopen's own EMCY consumer chokes on 2-byte (MDi) EMCYs
    return storage, faults
