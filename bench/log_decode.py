"""Offline CAN log decoding: `servodesk decode-log` against tshark on the same frames.

Generates a realistic bus recording (4 drives at 1 kHz SYNC: TPDO1/TPDO2 per drive, an RPDO from
the master, 100 ms heartbeats, expedited and segmented SDO traffic with the odd abort, EMCYs)
as a candump .log and as a SocketCAN pcap, then prints:

- frames/s of `servodesk decode-log FILE -o OUT` (text) and of `tshark -T fields` with the
  NMT/SDO/EMCY fields on the pcap, 1,000,000 frames each (target: ours ≥ 1× tshark's rate);
- peak resident memory of `servodesk decode-log` at 1 M and 4 M frames (target: 4 M ≤ 1.2×).

Wall time includes each process's start-up. Run: `make bench` or
`.venv/bin/python bench/log_decode.py [--frames 1000000] [--big 4000000]`.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

from servodesk.logs.pcap import PcapWriter, tshark_command

RATE_TARGET = 1.0  # ours / tshark frames per second
MEMORY_TARGET = 1.2  # peak RSS at the big log / at the 1 M log
NODES = (1, 2, 3, 4)
START = 1_700_000_000.0


def frames(count: int) -> Iterator[tuple[float, int, bytes]]:
    """A bus at 1 kHz SYNC; every cycle: SYNC, TPDO1 + TPDO2 of each drive, one master RPDO;
    every 10th cycle an SDO exchange; heartbeats every 100 ms; an EMCY and an abort now and
    then. Deterministic (no randomness), so every run decodes the same frames."""
    emitted = 0
    cycle = 0
    position = 0
    while True:
        t = START + cycle * 0.001
        position = (position + 37) & 0xFFFFFFFF
        batch: list[tuple[int, bytes]] = [(0x080, b"")]
        for node in NODES:
            status = (0x0237).to_bytes(2, "little")
            batch.append((0x180 + node, status + position.to_bytes(4, "little") + b"\x01\x00"))
            batch.append((0x280 + node, (cycle & 0xFFFF).to_bytes(2, "little") + bytes(6)))
        batch.append((0x200 + NODES[cycle % 4], b"\x0f\x00" + position.to_bytes(4, "little")))
        if cycle % 10 == 0:
            node = NODES[(cycle // 10) % 4]
            step = (cycle // 10) % 40
            if step == 7:  # segmented upload of the device name
                batch += [
                    (0x600 + node, bytes.fromhex("40 08 10 00 00 00 00 00")),
                    (0x580 + node, bytes.fromhex("41 08 10 00 0B 00 00 00")),
                    (0x600 + node, bytes.fromhex("60 00 00 00 00 00 00 00")),
                    (0x580 + node, b"\x00DVS_CAN"),
                    (0x600 + node, bytes.fromhex("70 00 00 00 00 00 00 00")),
                    (0x580 + node, b"\x17OPEN\x00\x00\x00"),
                ]
            elif step == 23:  # a refused write
                batch += [
                    (0x600 + node, bytes.fromhex("2B 5A 60 00 03 00 00 00")),
                    (0x580 + node, bytes.fromhex("80 5A 60 00 30 00 09 06")),
                ]
            else:  # statusword read
                batch += [
                    (0x600 + node, bytes.fromhex("40 41 60 00 00 00 00 00")),
                    (0x580 + node, bytes.fromhex("4B 41 60 00 37 02 00 00")),
                ]
        if cycle % 100 == 0:
            batch += [(0x700 + node, b"\x05") for node in NODES]
        if cycle % 5000 == 2500:
            batch.append((0x083, bytes.fromhex("11 86 21 00 00 00 00 00")))
        for i, (can_id, data) in enumerate(batch):
            yield t + i * 0.00003, can_id, data
            emitted += 1
            if emitted == count:
                return
        cycle += 1


def write_candump(path: Path, count: int) -> None:
    with path.open("w", encoding="ascii") as out:
        lines: list[str] = []
        for t, can_id, data in frames(count):
            lines.append(f"({t:.6f}) can0 {can_id:03X}#{data.hex().upper()}\n")
            if len(lines) >= 10_000:
                out.writelines(lines)
                lines.clear()
        out.writelines(lines)


def write_pcap(path: Path, count: int) -> None:
    with path.open("wb") as out:
        writer = PcapWriter(out)
        for t, can_id, data in frames(count):
            writer.write(t, can_id, data)


def run(command: list[str]) -> tuple[float, float]:
    """(wall seconds, peak RSS MB) of one child process, measured by the kernel (wait4)."""
    start = time.perf_counter()
    child = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _pid, status, usage = os.wait4(child.pid, 0)
    elapsed = time.perf_counter() - start
    if status != 0:
        raise SystemExit(f"{command[0]} failed ({status}): {' '.join(command)}")
    return elapsed, usage.ru_maxrss / 1024  # Linux: KB


def ours(log: Path, out: Path) -> list[str]:
    return [sys.executable, "-m", "servodesk.cli", "decode-log", str(log), "-o", str(out)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=1_000_000)
    parser.add_argument("--big", type=int, default=4_000_000)
    args = parser.parse_args()
    tshark = shutil.which("tshark")
    with tempfile.TemporaryDirectory(prefix="servodesk-bench-") as tmp:
        folder = Path(tmp)
        log, pcap, big = folder / "bus.log", folder / "bus.pcap", folder / "big.log"
        started = time.perf_counter()
        write_candump(log, args.frames)
        write_pcap(pcap, args.frames)
        write_candump(big, args.big)
        took = time.perf_counter() - started
        size = log.stat().st_size / 1e6
        print(
            f"generated {args.frames:,} + {args.big:,} frames in {took:.1f} s ({size:.0f} MB log)"
        )

        seconds, rss = run(ours(log, folder / "out.txt"))
        our_rate = args.frames / seconds
        print(f"servodesk decode-log: {our_rate:,.0f} frames/s ({seconds:.2f} s), "
              f"peak RSS {rss:.0f} MB at {args.frames:,} frames")  # fmt: skip
        if tshark is not None:
            t_seconds, t_rss = run(tshark_command(tshark, pcap))
            their_rate = args.frames / t_seconds
            print(f"tshark -T fields:     {their_rate:,.0f} frames/s ({t_seconds:.2f} s), "
                  f"peak RSS {t_rss:.0f} MB")  # fmt: skip
            ratio = our_rate / their_rate
            verdict = "ok" if ratio >= RATE_TARGET else "below target"
            print(f"rate ratio ours/tshark: {ratio:.2f} (target ≥ {RATE_TARGET:g}): {verdict}")
        else:
            print("tshark not installed (make system-deps): no rate comparison")

        big_seconds, big_rss = run(ours(big, folder / "big.txt"))
        print(f"servodesk decode-log: {args.big / big_seconds:,.0f} frames/s ({big_seconds:.2f} s),"
              f" peak RSS {big_rss:.0f} MB at {args.big:,} frames")  # fmt: skip
        growth = big_rss / rss
        verdict = "ok" if growth <= MEMORY_TARGET else "above target"
        print(f"memory ratio {args.big:,} / {args.frames:,} frames: {growth:.2f}"
              f" (target ≤ {MEMORY_TARGET:g}): {verdict}")  # fmt: skip


if __name__ == "__main__":
    main()
