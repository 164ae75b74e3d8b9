"""The heartbeat monitor against running simulated drives: heartbeat age, lost and back."""

from __future__ import annotations

import asyncio
import time

import pytest

from servodesk.errors import CommTimeoutError
from tests.backend.network_rig import eventually, sim_rig

PERIOD_MS = 100
TICK_S = 0.2


@pytest.mark.anyio
async def test_heartbeat_age_stays_under_two_periods() -> None:
    async with sim_rig() as rig:
        await rig.registry.scan(sdo_sweep=True, timeout_ms=50)
        await rig.registry.set_heartbeat(1, 250)
        await eventually(lambda: rig.registry.info(1).heartbeat_age_ms is not None, what="beat")
        for _ in range(5):
            await asyncio.sleep(0.1)
            row = next(r for r in rig.registry.live() if r["node"] == 1)
            assert row["online"]
            assert row["heartbeat_age_ms"] < 2 * 250
            assert row["nmt_state"] == "pre-operational"
        # node 2 sends no heartbeat: no age
        row = next(r for r in rig.registry.live() if r["node"] == 2)
        assert row["heartbeat_age_ms"] is None
        assert row["online"]


@pytest.mark.anyio
async def test_silent_drives_are_lost_and_come_back() -> None:
    settings_lost_s = 1.5 * PERIOD_MS / 1000
    async with sim_rig() as rig:
        registry = rig.registry
        await registry.scan(sdo_sweep=True, timeout_ms=50)
        await registry.set_heartbeat(1, PERIOD_MS)
        await registry.set_heartbeat(3, PERIOD_MS)
        await eventually(lambda: registry.info(3).heartbeat_age_ms is not None, what="beats")

        rig.sim.stop()  # the drives lose power
        stopped = time.monotonic()
        await eventually(
            lambda: len(rig.events_of("node-lost")) >= 2, timeout=3.0, what="node-lost"
        )
        took = time.monotonic() - stopped
        # within the lost time plus one evaluation tick (and scheduling slack)
        assert took < settings_lost_s + TICK_S + 1.0
        assert {e.node for e in rig.events_of("node-lost")} == {1, 3}
        assert not registry.info(1).online
        assert registry.info(1).nmt_state.value == "unknown"

        # node 2 never sent heartbeats: silence alone does not make it lost...
        await asyncio.sleep(settings_lost_s + TICK_S)
        assert registry.info(2).online
        # ...a request it does not answer does
        with pytest.raises(CommTimeoutError):
            await registry.session(2).upload(0x1000, 0)  # Device type
        await eventually(lambda: bool(rig.events_of("node-lost", 2)), what="node 2 lost")

        rig.restart_drives()  # power back: boot-ups, then heartbeats at the stored period
        await eventually(
            lambda: {e.node for e in rig.events_of("node-back")} >= {1, 2, 3},
            what="node-back for every drive",
        )
        assert all(info.online for info in registry.all())
        assert {e.node for e in rig.events_of("boot-up")} == {1, 2, 3}
