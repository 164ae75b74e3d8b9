"""Rig for the bus / registry / scan / monitor tests: simulated drives on a private virtual
channel, a BusManager connected to it with its own bus instance, and a NodeRegistry on top.

The drives are started by the test (not by the manager's simulated mode) so a test can stop and
restart them, or add other devices to the same channel.
"""

from __future__ import annotations

import asyncio
import threading
import time
import uuid
from collections.abc import AsyncIterator, Callable, Sequence
from contextlib import asynccontextmanager
from dataclasses import dataclass, field

import can

from servodesk.bus.connection import BusFactory, BusManager
from servodesk.events.bus import BusEvent
from servodesk.models.bus import BusConfig, BusState
from servodesk.nodes.registry import NodeRegistry
from servodesk.settings import Settings
from servodesk_sim.runner import SimBus, SimNode, run_drives

SIM_DRIVES: tuple[tuple[int, str], ...] = ((1, "mdi-s1c"), (2, "kinco"), (3, "cia402"))


def fast_settings() -> Settings:
    """Short timeouts so failure paths take tenths of seconds, not seconds."""
    return Settings(
        simulated=False,
        sdo_timeout=0.2,
        heartbeat_lost_factor=1.5,
        default_heartbeat_timeout=1.0,
        reconnect_initial_delay=0.05,
        reconnect_max_delay=0.2,
        boot_wait=2.0,
    )


def new_channel() -> str:
    return f"test-net-{uuid.uuid4().hex}"


@dataclass
class Rig:
    channel: str
    drive_bus: can.BusABC
    sims: list[SimBus]
    bus: BusManager
    registry: NodeRegistry
    events: list[BusEvent] = field(default_factory=list)

    @property
    def sim(self) -> SimBus:
        return self.sims[-1]

    def restart_drives(self, nodes: Sequence[SimNode] | None = None) -> SimBus:
        """Power the (stopped) drives on again: same objects, so they keep their settings."""
        sim = SimBus(self.drive_bus, list(self.sim.nodes if nodes is None else nodes))
        sim.start()
        self.sims.append(sim)
        return sim

    def events_of(self, kind: str, node: int | None = None) -> list[BusEvent]:
        return [e for e in self.events if e.kind == kind and (node is None or e.node == node)]


@asynccontextmanager
async def sim_rig(
    drives: Sequence[tuple[int, str]] = SIM_DRIVES,
    *,
    settings: Settings | None = None,
    bus_factory: BusFactory | None = None,
    connect: bool = True,
) -> AsyncIterator[Rig]:
    settings = settings or fast_settings()
    channel = new_channel()
    drive_bus = can.Bus(interface="virtual", channel=channel)
    sims = [run_drives(drive_bus, drives)] if drives else []
    manager = BusManager(settings, bus_factory=bus_factory)
    registry = NodeRegistry(manager, settings)
    rig = Rig(channel, drive_bus, sims, manager, registry)
    registry.events.subscribe(rig.events.append)
    try:
        if connect:
            status = await manager.connect(BusConfig(interface="virtual", channel=channel))
            if status.state is not BusState.CONNECTED:
                raise RuntimeError(f"rig could not connect: {status}")
        yield rig
    finally:
        await registry.close()
        await manager.close()
        for sim in sims:
            sim.stop()
        drive_bus.shutdown()


async def eventually(
    condition: Callable[[], bool], *, timeout: float = 3.0, what: str = "condition"
) -> float:
    """Poll `condition` until it holds; returns the seconds it took (fails after `timeout`)."""
    started = time.monotonic()
    while not condition():
        if time.monotonic() - started > timeout:
            raise AssertionError(f"{what} did not happen within {timeout} s")
        await asyncio.sleep(0.01)
    return time.monotonic() - started


class Plug:
    """The cable of a fake USB adapter: pulled, every bus call fails; pushed back, it works."""

    def __init__(self) -> None:
        self.pulled = threading.Event()
        self.opened = 0  # buses the factory built


class UnpluggableBus(can.BusABC):
    """A virtual bus that raises like a lost adapter while its plug is pulled."""

    def __init__(self, inner: can.BusABC, plug: Plug) -> None:
        self.inner = inner
        self.plug = plug
        self.channel_info = f"unpluggable {inner.channel_info}"
        super().__init__(channel=inner.channel_info)

    def _recv_internal(self, timeout: float | None) -> tuple[can.Message | None, bool]:
        if self.plug.pulled.is_set():
            raise can.CanOperationError("adapter unplugged (recv)")
        return self.inner.recv(timeout), True

    def send(self, msg: can.Message, timeout: float | None = None) -> None:
        if self.plug.pulled.is_set():
            raise can.CanOperationError("adapter unplugged (send)")
        self.inner.send(msg, timeout)

    def shutdown(self) -> None:
        super().shutdown()
        self.inner.shutdown()


def unpluggable_factory(plug: Plug) -> BusFactory:
    def factory(config: BusConfig) -> can.BusABC:
        if plug.pulled.is_set():
            raise can.CanInitializationError("no such adapter")
        plug.opened += 1
        return UnpluggableBus(can.Bus(interface="virtual", channel=config.channel), plug)

    return factory
