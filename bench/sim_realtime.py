"""Real-time behaviour of the simulated drives at 1 kHz SYNC.

Four simulated drives share one virtual bus; node 1 (MDi-S1-C) produces SYNC every 1000 µs
(1005h bit 30, 1006h) and every drive sends two synchronous TPDOs (type 1) on each SYNC. A
listener on another bus instance records every frame with its send timestamp and prints:

- SYNC period error |period - 1 ms|: p50 / p99 / max
- SYNC -> TPDO latency (to the last of the 8 TPDOs of that cycle): p50 / p99
- missed cycles: SYNC periods over 1.5 ms, plus cycles that did not get all 8 TPDOs

Target (issue: simulated drives): p99 period error <= 0.5 ms and no missed cycles.

`--producer` chooses who sends the SYNC:
- `sim` (default): the simulated MDi (1005h bit 30), as above;
- `tool`: ServoDesk's own SYNC producer (network/sync.py): canopen's SyncProducer on python-can's
  cyclic send task (a thread on virtual/socketcand, the kernel's broadcast manager on SocketCAN);
- `stream`: an IP stream's SYNC, sent from a thread on the stream's own clock (motion/ip_timing.py
  `SyncClock`: absolute deadlines; a SYNC more than half a period late delays the rest instead
  of bursting), as motion/ip.py does, there paired with each set-point.
For `tool` and `stream` every frame is stamped when it is sent (python-can's virtual bus) and
read from a second bus instance after the run, so no reader thread competes with the sender.

Run: `make bench` or `.venv/bin/python bench/sim_realtime.py [--seconds 10] [--producer tool]`;
under load, start two `python -c "while True: pass"` first.
"""

from __future__ import annotations

import argparse
import collections
import gc
import itertools
import statistics
import sys
import time
from dataclasses import dataclass

import can
import canopen

from servodesk.motion.ip_timing import SyncClock
from servodesk_sim.frames import Frame
from servodesk_sim.runner import SimBus, run_drives

CHANNEL = "servodesk-bench-realtime"
NODES = [(1, "mdi-s1c"), (2, "kinco"), (3, "cia402"), (4, "mdi-s1c")]
PERIOD_US = 1000
SYNC_ID = 0x080


def sdo_write(bus: can.BusABC, node: int, index: int, sub: int, value: int, size: int) -> None:
    """Expedited SDO download with raw frames (no canopen client threads in the measurement)."""
    command = {1: 0x2F, 2: 0x2B, 4: 0x23}[size]
    payload = bytes([command, index & 0xFF, index >> 8, sub]) + value.to_bytes(4, "little")
    bus.send(can.Message(arbitration_id=0x600 + node, data=payload, is_extended_id=False))
    deadline = time.monotonic() + 1.0
    while time.monotonic() < deadline:
        reply = bus.recv(0.1)
        if reply is None or reply.arbitration_id != 0x580 + node:
            continue
        if reply.data[0] == 0x80:
            code = int.from_bytes(reply.data[4:8], "little")
            raise RuntimeError(f"node {node}: {index:04X}h:{sub} aborted {code:#010x}")
        return
    raise TimeoutError(f"node {node}: no SDO answer for {index:04X}h:{sub}")


def configure(bus: can.BusABC) -> None:
    for node, _profile in NODES:
        for n, mapping in ((0, [0x60410010, 0x60640020]), (1, [0x60610008, 0x606C0020])):
            comm, maps = 0x1800 + n, 0x1A00 + n
            cob = (0x180 + 0x100 * n) + node
            sdo_write(bus, node, comm, 1, 0x80000000 | 0x40000000 | cob, 4)  # TPDO invalid
            sdo_write(bus, node, comm, 2, 1, 1)  # transmission type 1: every SYNC
            sdo_write(bus, node, maps, 0, 0, 1)
            for sub, entry in enumerate(mapping, start=1):
                sdo_write(bus, node, maps, sub, entry, 4)
            sdo_write(bus, node, maps, 0, len(mapping), 1)
            sdo_write(bus, node, comm, 1, 0x40000000 | cob, 4)  # valid
    sdo_write(bus, 1, 0x1006, 0, PERIOD_US, 4)  # Communication cycle period
    bus.send(can.Message(arbitration_id=0x000, data=b"\x01\x00", is_extended_id=False))


@dataclass
class Result:
    syncs: int
    period_err_ms: list[float]
    latency_ms: list[float]
    missed: int
    bursts: int  # intervals under half a period: missed SYNCs sent late, back to back


def measure(bus: can.BusABC, sim: SimBus, seconds: float) -> Result:
    """Record every frame as the simulator puts it on the bus (a tap on the runner: the same
    instant a listener's virtual bus would stamp), so the measurement adds no reader thread
    competing for the interpreter with the drives."""
    tpdo_ids = {0x180 + node for node, _ in NODES} | {0x280 + node for node, _ in NODES}
    seen: list[tuple[float, int]] = []

    def tap(frame: Frame, _origin: object | None) -> None:
        seen.append((time.perf_counter(), frame.can_id))

    remove = sim.add_tap(tap)
    sdo_write(bus, 1, 0x1005, 0, 0x40000080, 4)  # SYNC producer on
    time.sleep(seconds)
    remove()
    sdo_write(bus, 1, 0x1005, 0, 0x80, 4)  # SYNC producer off
    sync_times: list[float] = []
    cycle_tpdos: list[list[float]] = []
    for stamp, can_id in seen:
        if can_id == SYNC_ID:
            sync_times.append(stamp)
            cycle_tpdos.append([])
        elif can_id in tpdo_ids and cycle_tpdos:
            cycle_tpdos[-1].append(stamp)
    # Drop the first and last cycles: start-up and the cut at the end.
    sync_times, cycle_tpdos = sync_times[1:-1], cycle_tpdos[1:-1]
    periods = [b - a for a, b in itertools.pairwise(sync_times)]
    period_err = [abs(p - PERIOD_US / 1e6) * 1e3 for p in periods]
    latency = [
        (max(tpdos) - t) * 1e3
        for t, tpdos in zip(sync_times, cycle_tpdos, strict=True)
        if len(tpdos) == len(tpdo_ids)
    ]
    late = sum(1 for p in periods if p > 1.5 * PERIOD_US / 1e6)
    incomplete = sum(1 for tpdos in cycle_tpdos if len(tpdos) != len(tpdo_ids))
    if incomplete:
        counts = collections.Counter(len(tpdos) for tpdos in cycle_tpdos)
        print(f"TPDOs per cycle (count: cycles): {dict(sorted(counts.items()))}")
    bursts = sum(1 for p in periods if p < 0.5 * PERIOD_US / 1e6)
    return Result(len(sync_times), period_err, latency, late + incomplete, bursts)


def measure_sent(recorder: can.BusABC, produce: str, master: can.BusABC, seconds: float) -> Result:
    """SYNC from the tool (`tool`: python-can's cyclic task; `stream`: a thread sleeping to
    absolute deadlines), measured from the send stamps of every frame on the channel."""
    period = PERIOD_US / 1e6
    if produce == "tool":
        network = canopen.Network(master)  # the bus is given: nothing to connect
        network.sync.start(period)
        time.sleep(seconds)
        network.sync.stop()  # type: ignore[no-untyped-call]  # canopen: unannotated
    else:
        sync = can.Message(arbitration_id=SYNC_ID, data=b"", is_extended_id=False)
        clock = SyncClock(time.perf_counter() + period, period)
        for k in range(int(seconds / period)):
            clock.wait(k)
            master.send(sync)
    time.sleep(0.05)  # the last cycle's TPDOs
    tpdo_ids = {0x180 + node for node, _ in NODES} | {0x280 + node for node, _ in NODES}
    sync_times: list[float] = []
    cycle_tpdos: list[list[float]] = []
    while (message := recorder.recv(0)) is not None:
        if message.arbitration_id == SYNC_ID:
            sync_times.append(message.timestamp)
            cycle_tpdos.append([])
        elif message.arbitration_id in tpdo_ids and cycle_tpdos:
            cycle_tpdos[-1].append(message.timestamp)
    sync_times, cycle_tpdos = sync_times[1:-1], cycle_tpdos[1:-1]
    periods = [b - a for a, b in itertools.pairwise(sync_times)]
    latency = [
        (max(tpdos) - t) * 1e3
        for t, tpdos in zip(sync_times, cycle_tpdos, strict=True)
        if len(tpdos) == len(tpdo_ids)
    ]
    late = sum(1 for p in periods if p > 1.5 * period)
    incomplete = sum(1 for tpdos in cycle_tpdos if len(tpdos) != len(tpdo_ids))
    bursts = sum(1 for p in periods if p < 0.5 * period)
    errors = [abs(p - period) * 1e3 for p in periods]
    return Result(len(sync_times), errors, latency, late + incomplete, bursts)


def percentile(values: list[float], q: float) -> float:
    if not values:
        return float("nan")
    return statistics.quantiles(values, n=1000, method="inclusive")[int(q * 10) - 1]


def main() -> int:
    sys.setswitchinterval(0.0002)
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--producer", choices=("sim", "tool", "stream"), default="sim")
    args = parser.parse_args()
    drive_bus = can.Bus(interface="virtual", channel=CHANNEL)
    master = can.Bus(interface="virtual", channel=CHANNEL)
    recorder: can.BusABC | None = None
    try:
        with run_drives(drive_bus, NODES) as sim:
            time.sleep(0.05)
            configure(master)
            gc.freeze()  # start-up objects (object dictionaries) need no more collection passes
            if args.producer == "sim":
                result = measure(master, sim, args.seconds)
            else:
                recorder = can.Bus(interface="virtual", channel=CHANNEL)
                result = measure_sent(recorder, args.producer, master, args.seconds)
            stats = sim.stats
    finally:
        for bus in (recorder, master, drive_bus):
            if bus is not None:
                bus.shutdown()
    p99_err = percentile(result.period_err_ms, 99)
    print(f"SYNC producer: {args.producer}")
    print(f"drives: {len(NODES)}, TPDOs per SYNC: {2 * len(NODES)}, period {PERIOD_US} us")
    print(f"SYNC cycles measured: {result.syncs}")
    print(
        f"SYNC period error ms: p50 {percentile(result.period_err_ms, 50):.3f}  "
        f"p99 {p99_err:.3f}  max {max(result.period_err_ms, default=float('nan')):.3f}"
    )
    print(
        f"SYNC->TPDO latency ms: p50 {percentile(result.latency_ms, 50):.3f}  "
        f"p99 {percentile(result.latency_ms, 99):.3f}"
    )
    print(f"missed cycles: {result.missed}")
    print(f"SYNC bursts (intervals under half a period): {result.bursts}")
    print(f"runner: {stats}")
    print(f"p99 period error / target 0.5 ms: {p99_err / 0.5:.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
