"""A quick stop of every drive reaches a jogging drive before the jog's own stop does."""

from __future__ import annotations

import time

import pytest

from tests.backend.motion_rig import CIA402
from tests.backend.safety_rig import safety_rig
from tests.backend.test_tool_heartbeat import Ear, sdo_requests

pytestmark = pytest.mark.anyio

CONTROLWORD = 0x6040


async def test_quick_stop_all_goes_before_the_jogs_own_stop() -> None:
    async with safety_rig() as rig:
        await rig.jog(CIA402)
        ear = Ear(rig.rig.channel)
        try:
            start = time.monotonic()
            result = await rig.safety.quick_stop_all()
            await rig.safety.jogs.settled()
        finally:
            ear.close()
        assert CIA402 in result.stopped
        requests = sdo_requests(ear, CIA402, start)
        # the first request to the jogging drive is the quick stop (0002h), not the halt's reads
        command, index, _ = requests[0]
        assert (command & 0xE0, index) == (0x20, CONTROLWORD), requests
