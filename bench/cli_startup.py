"""How long the command line takes for what a user types most: `servodesk --help` and
`servodesk eds-check` of a small file, each as a whole process, against `python -c pass`.

Every command imports what it uses (servodesk/cli.py): python-can alone brings asammdf, numpy
and pandas (about a second) and is needed only by the commands that open a bus or read a log.

Targets (median of --runs): `--help` <= 0.5 s, `eds-check` of a small file <= 1 s. Prints each
figure, its ratio to the target and to a bare interpreter; exits non-zero on a miss. Run:
`make bench` or `.venv/bin/python bench/cli_startup.py`.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

SHARED = Path(__file__).resolve().parents[2] / "shared"
SMALL_EDS = SHARED / "eds" / "Sevcon_sevcon_gen4_simstub.eds"  # 2.6 kB, 8 objects
TARGETS = {"--help": 0.5, "eds-check": 1.0}


def timed(command: list[str], runs: int) -> float:
    """Median wall time of `command` as a new process, output discarded."""
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=7)
    args = parser.parse_args()
    servodesk = [sys.executable, "-m", "servodesk.cli"]
    bare = timed([sys.executable, "-c", "pass"], args.runs)
    print(f"python -c pass: {bare:.3f} s (median of {args.runs})")
    commands = {
        "--help": [*servodesk, "--help"],
        "eds-check": [*servodesk, "eds-check", str(SMALL_EDS)],
    }
    met = True
    for name, command in commands.items():
        seconds = timed(command, args.runs)
        target = TARGETS[name]
        ok = seconds <= target
        met &= ok
        print(
            f"servodesk {name}: {seconds:.3f} s = {seconds / bare:.1f}x python -c pass; "
            f"target <= {target} s: {seconds / target:.2f}x of it {'ok' if ok else 'MISSED'}"
        )
    load = " ".join(f"{x:.1f}" for x in os.getloadavg())
    print(f"load average {load} on {os.cpu_count()} CPUs")
    print("targets met" if met else "targets NOT met")
    return 0 if met else 1


if __name__ == "__main__":
    raise SystemExit(main())
