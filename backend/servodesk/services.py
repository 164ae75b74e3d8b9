"""The services of one running app, built together and owned by the app's lifespan (no global
singletons for live state: tests build as many independent apps as they like)."""

from __future__ import annotations

from dataclasses import dataclass

from servodesk.bus.connection import BusFactory, BusManager
from servodesk.live import LiveHub
from servodesk.motion.safety import MotionSafety
from servodesk.motion.service import MotionService
from servodesk.network.sync import SyncService
from servodesk.nodes.registry import NodeRegistry
from servodesk.od.parser import OdParser
from servodesk.params.node_id import NodeIdService
from servodesk.params.paramsets import ParamSetService
from servodesk.params.service import ParamService
from servodesk.pdo.service import PdoService
from servodesk.sdo.jobs import JobManager
from servodesk.sdo.service import SdoService
from servodesk.settings import Settings


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

    async def open(self) -> None:
        """What must run before the bus connects (nothing is missed)."""

    def start(self) -> None:
        self.safety.start()
        self.live.start()

    async def close(self) -> None:
        self.od_parser.close()
        await self.live.close()
        # before the registry and bus go: running jogs are stopped, 1016h entries restored
        await self.safety.close()
        self.pdos.close()
        await self.jobs.close()
        self.sync.close()
        await self.registry.close()
        await self.bus.close()


def build_services(settings: Settings, *, bus_factory: BusFactory | None = None) -> Services:
    bus = BusManager(settings, bus_factory=bus_factory)
    registry = NodeRegistry(bus, settings)
    jobs = JobManager(registry)
    registry.add_od_listener(jobs.dictionary_changed)
    od_parser = OdParser()
    sync = SyncService(bus)
    pdos = PdoService(
        registry,
        known_nodes=lambda: [info.node for info in registry.all()],
        network=lambda: bus.network,
        bitrate=lambda: bus.status().bitrate,
        sync=sync.get,
    )
    # the cached PDOs go stale on a dictionary change, NMT command, boot-up, bus change or a raw
    # SDO write to a PDO parameter (SdoService on_write; a DCF load tells the service itself)
    registry.add_od_listener(pdos.forget)
    registry.add_event_listener(pdos.on_event)
    bus.add_listener(pdos.on_bus)
    motion = MotionService(registry, settings, pdos, sync=sync)
    safety = MotionSafety(motion, bus, registry, settings)
    return Services(
        settings=settings,
        bus=bus,
        registry=registry,
        sync=sync,
        sdo=SdoService(registry, on_write=pdos.sdo_written),
        jobs=jobs,
        params=ParamService(registry),
        node_ids=NodeIdService(registry, settings),
        paramsets=ParamSetService(registry, od_parser, pdos),
        pdos=pdos,
        motion=motion,
        safety=safety,
        live=LiveHub(bus, registry, safety),
        od_parser=od_parser,
    )
