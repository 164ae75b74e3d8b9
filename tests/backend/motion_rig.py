"""Rig for the motion service tests: the three simulated drives on a private virtual channel,
the app's registry (so NMT states are tracked as in the app) and a MotionService on top."""

from __future__ import annotations

import asyncio
import time
from collections.abc import AsyncIterator, Callable
from contextlib import asynccontextmanager
from dataclasses import dataclass

from servodesk.models.motion import DriveState
from servodesk.motion.service import MotionService
from servodesk.network.sync import SyncService
from servodesk.settings import Settings
from tests.backend.network_rig import Rig, fast_settings, sim_rig

MDI, KINCO, CIA402 = 1, 2, 3
NODES = (MDI, KINCO, CIA402)
SIM_NEG_LIMIT = 0x5FF1  # SIM negative limit switch position (motor increments)
SIM_POS_LIMIT = 0x5FF2  # SIM positive limit switch position
SIM_INJECT_FAULT = 0x5FF0  # SIM inject fault


@dataclass
class MotionRig:
    rig: Rig
    motion: MotionService
    sync: SyncService

    async def write(self, node: int, index: int, sub: int, value: int, size: int = 4) -> None:
        data = value.to_bytes(size, "little", signed=value < 0)
        await self.rig.registry.session(node).download(index, sub, data)

    async def read(self, node: int, index: int, sub: int = 0, *, signed: bool = True) -> int:
        data = await self.rig.registry.session(node).upload(index, sub)
        return int.from_bytes(data, "little", signed=signed)

    async def until(
        self, node: int, test: Callable[[DriveState], bool], *, timeout: float, what: str
    ) -> DriveState:
        """Poll the drive state until `test` holds (fails after `timeout` s of simulated time,
        which runs at real time)."""
        started = time.monotonic()
        while True:
            state = await self.motion.state(node)
            if test(state):
                return state
            if time.monotonic() - started > timeout:
                raise AssertionError(f"node {node}: {what} not within {timeout} s: {state}")
            await asyncio.sleep(0.02)

    async def widen_switches(self, node: int, rev: int = 1000) -> None:
        """Move the simulated limit switches out of the way of long jogs."""
        await self.write(node, SIM_NEG_LIMIT, 0, -rev * 131072)
        await self.write(node, SIM_POS_LIMIT, 0, rev * 131072)


def motion_settings() -> Settings:
    settings = fast_settings()
    return settings.model_copy(update={"sdo_timeout": 0.3, "motion_transition_timeout": 0.3})


@asynccontextmanager
async def motion_rig(settings: Settings | None = None) -> AsyncIterator[MotionRig]:
    settings = settings or motion_settings()
    async with sim_rig(settings=settings) as rig:
        await rig.registry.settled()
        for node in NODES:
            if not rig.registry.known(node):
                await rig.registry.add(node)
        sync = SyncService(rig.bus)
        try:
            yield MotionRig(rig, MotionService(rig.registry, settings, sync=sync), sync)
        finally:
            sync.close()
