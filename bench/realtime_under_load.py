"""Issue 18's real-time targets under load, side by side as measured / target.

The drives and the app run in separate processes, as in bench/jog_stop.py: the simulated drives
in `servodesk-sim --serve` (socketcand on loopback), the app as `servodesk serve -i socketcand`,
and `--hogs` CPU-bound processes (2) beside them from before the app starts. For the whole timed
run a scope capture of 5 signals at 1 kHz with the Scope page's poll (bench/quick_stop_load.py)
and what the other pages poll (bench/soak.py) run, each in a process of its own, and Chromium
(/usr/bin/chromium, headless) renders the Scope page with its viewer following the capture
(`--no-browser`: without it). This process listens on the bus with its own socketcand client,
stamping frames as they arrive (CLOCK_MONOTONIC is shared by all processes); its only other
thread is that listener's.

The timed run (`--duration` s: 120, the CI run; 1800 for the 30-minute soak; at least one round
of each condition) goes round the conditions idle, a scan (POST /api/scan), an upload-all of
node 3, a DCF load (node 2's own parameter set written back) and a log decode, each worked in a
process of its own; in each, trials on node 3:
- quick stop over REST and over the WebSocket → controlword 0002h on the bus (quick_stop_load);
- jog start (POST …/jog, PV 300 rpm) → the first set-point 60FFh on the bus;
- keep-alive loss → halt on the bus (bench/jog_stop.py (a)).
Node 3's RPDOs are read as the object writes they carry, through the mapping the app reports
(GET /api/nodes/3/pdos): a stop or set-point sent in an RPDO counts like one sent by SDO.
A trial whose frame never came counts as infinitely late.

Also: the event loop's lag (GET /api/health `loop`, the last minute) after the start-up and
after each kind of trial in each condition, judged on the worst reading; heartbeat-consumer trips
(a drive's EMCY of a lost tool heartbeat: MDi alarm 61, Kinco 8120h, CiA 402 8130h) during the
run; and before the app starts, on their own: the SDO read's overhead through the API
(bench/sdo_overhead.py, its owner's measurement, in its own app) and the SYNC producer's period
error (bench/sync_timing.py, quiet, and beside the CPU hogs: reported, no target).

Exits non-zero on a miss. Not part of the test run. Run: `make bench` or
`.venv/bin/python bench/realtime_under_load.py [--duration 1800] [--trials 10] [--hogs 2]`.
"""

from __future__ import annotations

import argparse
import json
import logging
import math
import re
import subprocess
import sys
import tempfile
import threading
import time
from collections import defaultdict
from collections.abc import Callable, Iterator
from contextlib import ExitStack, contextmanager
from dataclasses import dataclass, field
from multiprocessing.synchronize import Event as EventType
from pathlib import Path
from typing import Any

import can
import httpx

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository, for bench/
from bench.jog_stop import (
    CLIENT,
    NODE,
    Ear,
    free_port,
    jog_body,
    keepalive_trials,
    ok,
    prepare_jog,
    report_p99,
    sim_process,
    start_app,
)
from bench.quick_stop_load import _scope, beside, cpu_hogs, rest_trials, work_process, ws_trials
from bench.soak import Focus, Load, page_polls, poller
from bench.sync_timing import SyncFigures

BENCH = Path(__file__).resolve().parent
CHROMIUM = Path("/usr/bin/chromium")
CONDITIONS = ("idle", "scan", "upload-all", "dcf-load", "log-decode")
DCF_NODE = 2
TARGET_VELOCITY = 0x60FF
TRIP_CODES = {1: 61, 2: 0x8120, 3: 0x8130}  # EMCY code of a lost heartbeat, per drive
RPDO_BASES = (0x200, 0x300, 0x400, 0x500)
TRIALS = {  # kind: (what on the bus ends it, target p99 ms)
    "quick stop REST": ("controlword", 30.0),
    "quick stop WS": ("controlword", 30.0),
    "jog start": ("first set-point", 50.0),
    "keep-alive loss": ("halt", 150.0),
}


# ---------------------------------------------------------------------- the bus


def sdo_write(msg: can.Message, index: int) -> int | None:
    """The value of an expedited SDO download of `index`:00 to node 3, else None."""
    data = bytes(msg.data)
    if msg.arbitration_id != 0x600 + NODE or len(data) < 8 or data[0] & 0xE0 != 0x20:
        return None
    if int.from_bytes(data[1:3], "little") != index or data[3] != 0:
        return None
    return int.from_bytes(data[4:8], "little")


def is_setpoint(msg: can.Message) -> bool:
    return bool(sdo_write(msg, TARGET_VELOCITY))  # a jog's set-point is never 0


def is_trip(msg: can.Message) -> bool:
    code = TRIP_CODES.get(msg.arbitration_id - 0x80)
    return code is not None and int.from_bytes(bytes(msg.data[:2]), "little") == code


class RunEar(Ear):
    """jog_stop's ear, also keeping node 3's RPDOs (read as the SDO writes they carry, so the
    matchers of the stop benches see them) and every drive's EMCY (counted as trips)."""

    def __init__(self, port: int) -> None:
        self.rpdos: dict[int, list[tuple[int, int, int]]] = {}  # COB-ID: (index, sub, bits)
        emcys = {0x80 + node for node in TRIP_CODES}
        self.WANTED = Ear.WANTED | emcys | {base + NODE for base in RPDO_BASES}
        self.trips: list[str] = []  # the heartbeat-consumer trips seen
        self.started = time.monotonic()
        super().__init__(port)

    def carried(self, msg: can.Message) -> list[can.Message]:
        """`msg`, and for an RPDO each byte-aligned object it maps as an SDO download."""
        found = [msg]
        bit = 0
        for index, sub, bits in self.rpdos.get(msg.arbitration_id, []):
            if bit % 8 == 0 and bits % 8 == 0 and bits <= 32 and (bit + bits) // 8 <= len(msg.data):
                value = bytes(msg.data[bit // 8 : (bit + bits) // 8]).ljust(4, b"\0")
                head = bytes([0x23, index & 0xFF, index >> 8, sub])
                found.append(
                    can.Message(
                        arbitration_id=0x600 + NODE, data=head + value, is_extended_id=False
                    )
                )
            bit += bits
        return found

    def first_after(
        self, since: float, match: Callable[[can.Message], bool], timeout: float = 3.0
    ) -> float:
        return super().first_after(since, lambda m: any(map(match, self.carried(m))), timeout)

    def count_trips(self, before: float = math.inf) -> None:
        """Count the trips among the frames kept from before `before`, and forget those."""
        with self._lock:
            old = [(at, msg) for at, msg in self.frames if at < before]
            self.frames = [(at, msg) for at, msg in self.frames if at >= before]
        for at, msg in old:
            if is_trip(msg):
                self.trips.append(f"node {msg.arbitration_id - 0x80} at {at - self.started:.1f} s")


def commission(http: httpx.Client) -> None:
    """Node 3 as a commissioned axis: the recommended mapping for profile velocity (statusword,
    mode, position, velocity, torque in TPDOs; controlword, mode and 60FFh in RPDOs), then
    Operational, so drive state comes from the frames and commands go in RPDOs."""
    pdos = ok(http.get(f"/api/nodes/{NODE}/pdos/recommended", params={"modes": "pv"}))["pdos"]
    for pdo in pdos:
        pdo.pop("transmission", None)
        pdo["mapping"] = [{k: o[k] for k in ("index", "subindex", "bits")} for o in pdo["mapping"]]
    ok(http.put(f"/api/nodes/{NODE}/pdos", json={"pdos": pdos}))
    ok(http.post(f"/api/nodes/{NODE}/nmt", json={"command": "start"}))
    mapped = [
        f"{p['kind'].upper()}{p['number']} "
        + "+".join(f"{o['index']:04X}h" for o in p["mapping"])
        + f" (type {p['transmission_type']})"
        for p in pdos
        if p["valid"]
    ]
    print(f"    node {NODE} mapped: {', '.join(mapped)}")


def read_rpdos(http: httpx.Client, ear: RunEar) -> None:
    answer = http.get(f"/api/nodes/{NODE}/pdos")
    if answer.status_code == 200:
        ear.rpdos = {
            p["cob_id"]: [(o["index"], o["subindex"], o["bits"]) for o in p["mapping"]]
            for p in answer.json()
            if p["kind"] == "rpdo" and p["valid"]
        }
        ear.WANTED = ear.WANTED | set(ear.rpdos)


# ---------------------------------------------------------------------- work beside the trials


def _scans(base: str, stop: EventType) -> None:
    with httpx.Client(base_url=base, timeout=60) as http:
        while not stop.is_set():
            http.post("/api/scan", json={})


def _dcf_loads(base: str, stop: EventType) -> None:
    with httpx.Client(base_url=base, timeout=120) as http:
        dcf = http.get(f"/api/nodes/{DCF_NODE}/dcf").content
        while not stop.is_set():
            http.post(f"/api/nodes/{DCF_NODE}/dcf", files={"file": ("node.dcf", dcf)})


def _pages(base: str, stop: EventType) -> None:
    """The Drive page of node 3, the Faults page, node list, bus and events (the Scope page's
    poll runs with the capture)."""
    halt, load = threading.Event(), Load()
    polls = page_polls(Focus(node=NODE), None)
    threads = [threading.Thread(target=poller, args=(base, *p, halt, load)) for p in polls]
    for thread in threads:
        thread.start()
    stop.wait()
    halt.set()
    for thread in threads:
        thread.join(30)


@contextmanager
def condition_work(condition: str, base: str, log_frames: int) -> Iterator[None]:
    mine = {"scan": (_scans, 1.0), "dcf-load": (_dcf_loads, 2.0)}
    if condition in mine:
        target, warm_up = mine[condition]
        with work_process(target, base, (), warm_up):
            yield
    else:
        with beside(condition, base, log_frames):
            yield


# ---------------------------------------------------------------------- trials


def jog_start_trial(http: httpx.Client, ear: RunEar) -> float:
    """From POST …/jog to its first set-point on the bus (ms); the jog is then let go."""
    prepare_jog(http)
    body = jog_body(500)
    sent = time.monotonic()
    jog_id = ok(http.post(f"/api/nodes/{NODE}/jog", headers=CLIENT, json=body))["jog_id"]
    try:
        try:
            at = ear.first_after(sent, is_setpoint)
        except RuntimeError:  # mapped into an RPDO as the jog started: read the mapping again
            read_rpdos(http, ear)
            at = ear.first_after(sent, is_setpoint, timeout=0.5)
    except RuntimeError:
        return math.inf
    finally:
        http.delete(f"/api/jog/{jog_id}")
    return (at - sent) * 1000


def each(trial: Callable[[], list[float]], count: int, http: httpx.Client) -> list[float]:
    """`count` runs of a one-trial helper; a trial that failed (no frame, the drive would not
    enable) counts as inf, and a fault of the drive (a trip) is reset for the next one."""
    values: list[float] = []
    for _ in range(count):
        try:
            values += trial()
        except RuntimeError as exc:
            print(f"    a trial failed: {str(exc)[:160]}")
            values.append(math.inf)
            http.post(f"/api/nodes/{NODE}/drive/fault-reset", headers=CLIENT)
    return values


@dataclass
class Results:
    trials: dict[str, dict[str, list[float]]] = field(
        default_factory=lambda: defaultdict(lambda: defaultdict(list))
    )  # kind: condition: ms
    lag: list[tuple[str, dict[str, Any]]] = field(default_factory=list)
    early: int = 0  # keep-alive trials whose jog stopped early (a keep-alive over 100 ms late)

    def read_lag(self, base: str, label: str) -> None:
        loop = httpx.get(f"{base}/api/health", timeout=30).json()["loop"]
        self.lag.append((label, loop))

    def all(self, kind: str) -> list[float]:
        return [v for values in self.trials[kind].values() for v in values]


def one_round(
    condition: str, base: str, http: httpx.Client, ear: RunEar, out: Results, n: int
) -> None:
    trials = out.trials
    trials["quick stop REST"][condition] += each(lambda: rest_trials(base, ear, 1), 2 * n, http)
    trials["quick stop WS"][condition] += each(lambda: ws_trials(base, ear, 1), 2 * n, http)
    out.read_lag(base, f"{condition}: quick stops")
    trials["jog start"][condition] += each(lambda: [jog_start_trial(http, ear)], n, http)
    out.read_lag(base, f"{condition}: jog starts")

    def keepalive_loss() -> list[float]:
        kept, early = keepalive_trials(http, ear, 1, lambda: None)
        out.early += early
        return kept

    trials["keep-alive loss"][condition] += each(keepalive_loss, n, http)
    out.read_lag(base, f"{condition}: keep-alive losses")


def timed_run(base: str, ear: RunEar, args: argparse.Namespace) -> Results:
    out = Results()
    out.read_lag(base, "start-up")
    capture_s = min(args.duration + 300.0, 3600.0)
    with ExitStack() as stack:
        http = stack.enter_context(httpx.Client(base_url=base, timeout=30))
        if args.mapped:  # before the capture maps its own TPDOs beside these
            commission(http)
        stack.enter_context(work_process(_scope, base, (capture_s,), 3.0))
        stack.enter_context(work_process(_pages, base, (), 1.0))
        if args.browser:
            stack.enter_context(viewer_browser(base))
        read_rpdos(http, ear)
        end = time.monotonic() + args.duration
        done = 0
        while done < len(CONDITIONS) or time.monotonic() < end:
            condition = CONDITIONS[done % len(CONDITIONS)]
            began = time.monotonic()
            print(f"    {began - ear.started:6.1f} s: {condition}")
            with condition_work(condition, base, args.log_frames):
                one_round(condition, base, http, ear, out, args.trials)
            ear.count_trips(before=began)
            done += 1
        http.delete(f"/api/nodes/{NODE}/drive/controller", headers=CLIENT)  # 1016h restored
        bus = http.get("/api/bus").json()
        print(f"    bus: {bus.get('reconnects')} reconnects, last error {bus.get('error')}")
    ear.count_trips()  # before the app stops: a stopped tool's heartbeat is not a trip
    return out


@contextmanager
def viewer_browser(base: str) -> Iterator[None]:
    """Chromium rendering the Scope page for the whole timed run: its rerun viewer follows the
    live capture (software rendering on this host, as on a laptop without a GPU driver)."""
    if not CHROMIUM.exists():
        print(f"    no {CHROMIUM}: the Scope page's viewer is not rendered beside the run")
        yield
        return
    with tempfile.TemporaryDirectory(prefix="servodesk-rt-chromium-") as profile:
        command = [
            str(CHROMIUM),
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--disable-background-networking",
            f"--user-data-dir={profile}",
            "--remote-debugging-port=0",  # keeps a headless browser open on its page
            "--window-size=1400,900",
            f"{base}/scope",
        ]
        browser = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            yield
        finally:
            browser.terminate()
            try:
                browser.wait(10)
            except subprocess.TimeoutExpired:
                browser.kill()


# ---------------------------------------------------------------------- measured apart


def sync_figures(seconds: float, hogs: int) -> SyncFigures | None:
    command = [sys.executable, str(BENCH / "sync_timing.py"), "--json", "--seconds", str(seconds)]
    done = subprocess.run([*command, "--hogs", str(hogs)], capture_output=True, text=True)
    try:
        return SyncFigures(**json.loads(done.stdout.strip().splitlines()[-1]))
    except (IndexError, ValueError, TypeError):
        print(f"bench/sync_timing.py failed: {done.stderr.strip()[-500:]}")
        return None


def sdo_added_ms() -> float | None:
    done = subprocess.run(
        [sys.executable, str(BENCH / "sdo_overhead.py")], capture_output=True, text=True
    )
    print("\n".join(f"    {line}" for line in done.stdout.strip().splitlines()))
    found = re.search(r"API adds (-?[\d.]+) ms median", done.stdout)
    if found is None:
        print(f"bench/sdo_overhead.py gave no figure: {done.stderr.strip()[-500:]}")
    return None if found is None else float(found.group(1))


# ---------------------------------------------------------------------- report


def p99(values: list[float]) -> float:
    """Nearest rank, as bench/jog_stop.py reads it."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(0.99 * (len(ordered) - 1)))] if ordered else math.nan


@dataclass(frozen=True)
class Row:
    name: str
    measured: float | None  # None: not measured
    target: float | None  # None: reported only
    unit: str = "ms"

    def print(self) -> bool:
        """One line of the table; True unless it misses its target."""
        value = "n/a" if self.measured is None else f"{self.measured:.3g} {self.unit}".strip()
        if self.target is None:
            print(f"{self.name:<46} {value:>12} {'(reported)':>12}")
            return True
        met = self.measured is not None and self.measured <= self.target
        ratio = "n/a" if self.measured is None else "-"  # a target of 0 has no ratio
        if self.measured is not None and self.target:
            ratio = f"{self.measured / self.target:.2f}"
        target = f"≤ {self.target:g} {self.unit}".strip()
        print(f"{self.name:<46} {value:>12} {target:>12} {ratio:>7}  {'ok' if met else 'MISS'}")
        return met


def details(out: Results) -> None:
    for kind, by_condition in out.trials.items():
        for condition, values in by_condition.items():
            report_p99(f"    {kind} ({condition})", values, TRIALS[kind][1])
    print(f"    keep-alive trials whose jog stopped early (a keep-alive late): {out.early}")
    for label, loop in out.lag:
        print(
            f"    loop lag, the minute up to the end of {label}: p50 {loop['p50_ms']} ms, "
            f"p99 {loop['p99_ms']} ms, max {loop['max_ms']} ms ({loop['samples']} samples)"
        )


def main() -> int:
    logging.getLogger("can.interfaces.socketcand").setLevel(logging.ERROR)  # split-frame warnings
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=120.0, help="s (1800: the soak)")
    parser.add_argument("--trials", type=int, default=10, help="per condition (quick stops: 2×)")
    parser.add_argument("--hogs", type=int, default=2, help="CPU-bound processes beside")
    parser.add_argument("--log-frames", type=int, default=1_000_000, help="the decoded log's")
    parser.add_argument("--sync-seconds", type=float, default=10.0)
    parser.add_argument(
        "--sdo-only",
        dest="mapped",
        action="store_false",
        help="leave node 3's PDOs as they boot (state by SDO) instead of the recommended ones",
    )
    parser.add_argument("--skip-apart", action="store_true", help="no SYNC / SDO benches first")
    parser.add_argument(
        "--no-browser",
        dest="browser",
        action="store_false",
        help="no Chromium rendering the Scope page's viewer beside the run",
    )
    args = parser.parse_args()
    quiet = loaded = None
    sdo = None
    if not args.skip_apart:
        print("SYNC producer (bench/sync_timing.py), quiet and beside the CPU hogs ...")
        quiet = sync_figures(args.sync_seconds, 0)
        loaded = sync_figures(args.sync_seconds, args.hogs)
        for figures in (quiet, loaded):
            print(f"    {figures.line() if figures else 'not measured'}")
        print("SDO read overhead (bench/sdo_overhead.py, its own app) ...")
        sdo = sdo_added_ms()
    can_port, http_port = free_port(), free_port()
    print(f"timed run: {args.duration:g} s at least, {args.hogs} CPU hogs, conditions {CONDITIONS}")
    data_dir = tempfile.mkdtemp(prefix="servodesk-rt-")  # kept: the server's log, for diagnosis
    with sim_process(can_port):
        ear = RunEar(can_port)
        try:
            with cpu_hogs(args.hogs):
                proc = start_app(can_port, http_port, data_dir)
                try:
                    out = timed_run(f"http://127.0.0.1:{http_port}", ear, args)
                finally:
                    proc.terminate()
                    proc.wait(20)
        finally:
            ear.close()
    details(out)
    print(f"    heartbeat-consumer trips (EMCY): {', '.join(ear.trips) or 'none'}")
    print(f"    the server's log: {data_dir}/server.log")
    rows = [
        Row("event-loop lag p99 (worst minute)", max(lag["p99_ms"] for _, lag in out.lag), 20.0),
        Row("event-loop lag max", max(lag["max_ms"] for _, lag in out.lag), 100.0),
        *(
            Row(f"{kind} -> {what} p99", p99(out.all(kind)), t)
            for kind, (what, t) in TRIALS.items()
        ),
        Row("heartbeat-consumer trips", len(ear.trips), 0, unit=""),
        Row("SDO read: API adds, median", sdo, 0.5),
        Row("SYNC period error p99, quiet", None if quiet is None else quiet.p99_ms, 0.5),
        Row(
            f"SYNC period error p99, {args.hogs} CPU hogs", loaded.p99_ms if loaded else None, None
        ),
    ]
    print(f"\n{'target':<46} {'measured':>12} {'target':>12} {'ratio':>7}  verdict")
    met = all([row.print() for row in rows])
    print("targets met" if met else "targets NOT met")
    return 0 if met else 1


if __name__ == "__main__":
    raise SystemExit(main())
