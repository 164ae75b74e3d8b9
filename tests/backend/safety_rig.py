"""Rig for the safety-layer tests: the motion rig's drives and MotionService, with the real
MotionSafety (lease, heartbeat guard, jog watchdog and its triggers) on top."""

from __future__ import annotations

from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass

from servodesk.bus.connection import BusFactory
from servodesk.models.motion import DriveState
from servodesk.models.safety import JogInfo, JogRequest
from servodesk.motion.lease import Client
from servodesk.motion.safety import MotionSafety
from servodesk.motion.service import MotionService
from servodesk.network.sync import SyncService
from tests.backend.motion_rig import NODES, MotionRig, motion_settings
from tests.backend.network_rig import eventually, sim_rig

PAGE = Client(id="page-a", name="Alice")
HALT = 0x0100  # controlword bit 8


@dataclass
class SafetyRig(MotionRig):
    safety: MotionSafety

    async def jog(self, node: int, rpm: float = 300, keepalive_ms: int = 500) -> JogInfo:
        await self.motion.enable(node)
        await self.widen_switches(node)
        request = JogRequest(mode="pv", velocity_rpm=rpm, keepalive_ms=keepalive_ms)
        info = await self.safety.start_jog(node, request, PAGE)
        # kept alive (as a page does) until it moves; each state read is an SDO round trip
        for _ in range(500):
            if (await self.motion.state(node)).velocity_rpm > rpm / 2:
                break
            self.keep(info)
        else:
            raise AssertionError(f"node {node} does not jog")
        self.keep(info)
        return info

    def keep(self, info: JogInfo) -> None:
        self.safety.keepalive(info.jog_id, PAGE)

    async def stopped(self, info: JogInfo) -> tuple[JogInfo, DriveState]:
        """Wait for the jog to be stopped and the axis to stand still."""
        jogs = self.safety.jogs
        await eventually(lambda: jogs.get(info.jog_id).state == "stopped", what="jog stopped")
        await jogs.settled()
        state = await self.until(
            info.node, lambda s: s.velocity_rpm == 0, timeout=5, what="standstill"
        )
        return jogs.get(info.jog_id), state


@asynccontextmanager
async def safety_rig(bus_factory: BusFactory | None = None) -> AsyncIterator[SafetyRig]:
    settings = motion_settings()
    async with sim_rig(settings=settings, bus_factory=bus_factory) as rig:
        await rig.registry.settled()
        for node in NODES:
            if not rig.registry.known(node):
                await rig.registry.add(node)
        sync = SyncService(rig.bus)
        motion = MotionService(rig.registry, settings, sync=sync)
        safety = MotionSafety(motion, rig.bus, rig.registry, settings)
        safety.start()
        try:
            yield SafetyRig(rig, motion, sync, safety)
        finally:
            await safety.close()
            sync.close()
