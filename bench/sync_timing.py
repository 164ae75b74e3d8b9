"""The tool's SYNC producer on time: period error of COB-ID 80h as sent, quiet and under load.

ServoDesk's own SyncService (network/sync.py) runs on a BusManager joined to a python-can virtual
channel, as in the app (its bus wrapper, canopen network, notifier thread and event loop). A
second bus instance on the channel keeps every frame stamped with the instant it was sent
(python-can's virtual bus stamps in `send`) and is read only after the run: no reader competes
with the sender. `--drives`: four simulated drives in this process answer every SYNC with two
TPDOs each (bench/sim_realtime.py's set-up), as in the app's simulated mode: the producer then
shares the interpreter with the drives' thread, and on a 2-core machine the process is CPU-bound
(the figure is the simulator's as much as the producer's; with a real adapter the drives are not
in the tool's process).

Printed: SYNC period error |interval − period| p50 / p99 / max, bursts (intervals under half a
period: missed SYNCs sent back to back), late intervals (over 1.5 periods), and the process's CPU
use. Target (issue 18): p99 ≤ 0.5 ms on a quiet host; under load (`--hogs 2`: two CPU-bound
processes) it is reported only. Exits non-zero when a quiet run misses it.

Run: `.venv/bin/python bench/sync_timing.py [--seconds 10] [--period-us 1000] [--hogs 2]
[--drives] [--json]`.
"""

from __future__ import annotations

import argparse
import asyncio
import gc
import itertools
import json
import resource
import sys
import time
import uuid
from dataclasses import asdict, dataclass
from pathlib import Path

import can

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository, for bench/
from bench.quick_stop_load import cpu_hogs
from bench.sim_realtime import NODES, configure, percentile

from servodesk.bus.connection import BusManager
from servodesk.heap import SWITCH_INTERVAL
from servodesk.models.bus import BusConfig, BusState
from servodesk.network.sync import SyncService
from servodesk.settings import Settings
from servodesk_sim.runner import run_drives

SYNC_ID = 0x080
TARGET_P99_MS = 0.5


@dataclass(frozen=True)
class SyncFigures:
    period_us: int
    hogs: int
    intervals: int
    p50_ms: float
    p99_ms: float
    max_ms: float
    bursts: int  # intervals under half a period
    late: int  # intervals over 1.5 periods
    drives: bool
    cpu_percent: float  # of one core, the whole process (the drives' too with --drives)

    def line(self) -> str:
        load = f"{self.hogs} CPU hogs" if self.hogs else "quiet"
        drives = ", drives in-process" if self.drives else ""
        return (
            f"SYNC {self.period_us} us ({load}{drives}): period error p50 {self.p50_ms:.3f} ms, "
            f"p99 {self.p99_ms:.3f} ms, max {self.max_ms:.3f} ms over {self.intervals} "
            f"intervals; bursts {self.bursts}, late {self.late}; CPU {self.cpu_percent:.0f}%"
        )


def figures(
    stamps: list[float], period_us: int, hogs: int, drives: bool, cpu: float
) -> SyncFigures:
    period = period_us / 1e6
    intervals = [b - a for a, b in itertools.pairwise(stamps)]
    errors = [abs(i - period) * 1000 for i in intervals]
    return SyncFigures(
        period_us=period_us,
        hogs=hogs,
        intervals=len(intervals),
        p50_ms=percentile(errors, 50),
        p99_ms=percentile(errors, 99),
        max_ms=max(errors, default=float("nan")),
        bursts=sum(1 for i in intervals if i < period / 2),
        late=sum(1 for i in intervals if i > 1.5 * period),
        drives=drives,
        cpu_percent=cpu,
    )


async def produce(channel: str, recorder: can.BusABC, period_us: int, seconds: float) -> float:
    """SyncService at `period_us` for `seconds`; returns the process's CPU use in % of a core."""
    manager = BusManager(Settings(simulated=False))
    sync = SyncService(manager)
    try:
        status = await manager.connect(BusConfig(interface="virtual", channel=channel))
        if status.state is not BusState.CONNECTED:
            raise RuntimeError(f"could not connect: {status}")
        while recorder.recv(0) is not None:  # the set-up's frames
            pass
        before, started = resource.getrusage(resource.RUSAGE_SELF), time.perf_counter()
        await sync.set(period_us)
        await asyncio.sleep(seconds)
        await sync.set(None)
        after, wall = resource.getrusage(resource.RUSAGE_SELF), time.perf_counter() - started
    finally:
        sync.close()
        await manager.close()
    used = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return 100 * used / wall


def measure(seconds: float, period_us: int, hogs: int, drives: bool = False) -> SyncFigures:
    channel = f"servodesk-bench-sync-{uuid.uuid4().hex[:8]}"
    drive_bus = can.Bus(interface="virtual", channel=channel)
    recorder = can.Bus(interface="virtual", channel=channel)
    sim = run_drives(drive_bus, NODES) if drives else None
    try:
        if sim is not None:
            time.sleep(0.05)
            configure(recorder)  # TPDOs 1 and 2 of every drive on each SYNC
        gc.freeze()  # the start-up objects need no more collection passes, as in the app
        with cpu_hogs(hogs):
            time.sleep(0.5 if hogs else 0)  # the hogs running before the first SYNC
            cpu = asyncio.run(produce(channel, recorder, period_us, seconds))
        stamps: list[float] = []
        while (message := recorder.recv(0)) is not None:
            if message.arbitration_id == SYNC_ID:
                stamps.append(message.timestamp)
    finally:
        if sim is not None:
            sim.stop()
        recorder.shutdown()
        drive_bus.shutdown()
    return figures(stamps[1:], period_us, hogs, drives, cpu)  # the first: the task's start


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--period-us", type=int, default=1000)
    parser.add_argument("--hogs", type=int, default=0, help="CPU-bound processes beside it")
    parser.add_argument("--drives", action="store_true", help="simulated drives in-process")
    parser.add_argument("--json", action="store_true", help="one JSON object, for other benches")
    args = parser.parse_args()
    sys.setswitchinterval(SWITCH_INTERVAL)  # as the app sets it
    result = measure(args.seconds, args.period_us, args.hogs, drives=args.drives)
    if args.json:
        print(json.dumps(asdict(result)))
    else:
        print(result.line())
        if not args.hogs:
            ratio = result.p99_ms / TARGET_P99_MS
            print(f"p99 period error / target {TARGET_P99_MS} ms: {ratio:.2f}")
    return 0 if args.hogs or result.p99_ms <= TARGET_P99_MS else 1


if __name__ == "__main__":
    raise SystemExit(main())
