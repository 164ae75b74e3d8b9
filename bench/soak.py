"""Soak: the app with its three simulated drives under a scope capture, UI polling and random
jogs for `--duration` seconds (default 120, the CI run; the documented run is 1800 s).

The app runs in this process (uvicorn in a thread, as tests/live_server.py `serve_simulated`
and bench/sim_under_load.py do), so its RSS is this process's RSS: the bench's own share here
is the capture start, a few HTTP calls a minute and an RSS sample every 5 s. For the whole run:

- a free-running scope capture at a 1000 µs SYNC period of node 1's 6064h and 606Ch and node
  2's 6064h (the scope adds each node's 6041h for its state lane), live view off
  (Settings(scope_live_view=False)), stopped with DELETE at the end;
- in a separate process (a browser is one), what the pages poll (frontend/src): GET
  /api/nodes/{n}/drive every 200 ms (useDrive POLL_MS, the node being jogged), GET
  …/drive/controller every 2 s (CONTROLLER_POLL_MS), GET /api/scope/captures/{id} every 250 ms
  (ScopePage POLL_MS), GET /api/nodes/{n}/faults every 2 s (FAULT_POLL_MS, the nodes in turn),
  and now and then (every 3 s; the frontend fetches these on changes) GET /api/nodes, /api/bus
  and /api/events;
- random jogs: a random node among those whose 6502h lists pv or pt, a random supported mode
  (pv: 10 rpm up to the node's max velocity; pt: 5 % up to its max torque, at most
  PT_TORQUE_CAP), once the axis is at rest (it coasts after a jog), the direction towards 0
  once it is more than STEER_REV motor revolutions out (limit switches 5FF1h/5FF2h moved to
  ±1000 rev first), held 0.5–3 s with POST /api/jog/{id}/keepalive every 100 ms (holdToRun
  KEEPALIVE_INTERVAL_MS; keepalive_ms 300 = KEEPALIVE_TIMEOUT_MS), then DELETE; one jog in
  QUICK_STOP_SHARE ends with POST …/drive/quick-stop instead, and the drive is enabled again.
  An axis still moving SETTLE_S after a jog ended or after that enable, and no longer slowing
  down, is a runaway (reported, then stopped with a short jog and DELETE).

Any 5xx or unexpected 4xx (or transport error) is an error. A jog the server stopped on its
own (keep-alive missed, EMCY, limit switch …: keep-alive answers 409 jog_stopped, or DELETE
finds it stopped) is counted apart with its reason; a quick stop's own 409 is expected.

Printed at the start, every minute and at the end: the app process's RSS, errors by route and
status, jogs and stops, API latency p50/p99/max per route (since the start), the capture's
samples against the expected count and lost, the sim runner's ticks/overruns/worst lateness.
Verdicts: RSS growth ≤ 20 MB (the target is for 30 minutes; the linear-fit trend in MB/min is
extrapolated to 30 minutes as well), zero errors, zero runaways, no capture samples lost.
`--no-capture` leaves the capture out (to tell its memory from the rest's).

Not part of the test run. Run: `make bench` (120 s) or
`.venv/bin/python bench/soak.py --duration 1800` (the documented 30-minute run).
"""

from __future__ import annotations

import argparse
import collections
import copy
import multiprocessing
import random
import socket
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import partial
from multiprocessing.queues import Queue
from pathlib import Path
from typing import TYPE_CHECKING, Any

import httpx
import numpy as np
import psutil  # type: ignore[import-untyped]  # no stubs installed; dev dependency

if TYPE_CHECKING:
    from fastapi import FastAPI

    from servodesk.settings import Settings
    from servodesk_sim.runner import SimBusStats

MB = 1024 * 1024
PERIOD_US = 1000
SIGNALS = [
    {"node": 1, "index": 0x6064},  # position actual value
    {"node": 1, "index": 0x606C},  # velocity actual value
    {"node": 2, "index": 0x6064},
]
NODES = (1, 2, 3)
CLIENT = {"X-Client-Id": "bench-soak", "X-Client-Name": "soak bench"}
SIM_LIMITS = ((0x5FF1, -1000), (0x5FF2, 1000))  # simulated N-OT/P-OT positions, revolutions
COUNTS_PER_REV = 131072
STEER_REV = 150.0  # motor revolutions (limit units): beyond this the next jog heads back to 0
# pt: node 1 (MDi-S1-C) answers a jog above 100 % with SDO abort 06090031h on 6071h although
# GET …/drive reports max_torque_pct 300 (6072h): capped here, reported by the bench's author
PT_TORQUE_CAP = 100.0
KEEPALIVE_S = 0.100  # holdToRun KEEPALIVE_INTERVAL_MS
KEEPALIVE_MS = 300  # holdToRun KEEPALIVE_TIMEOUT_MS
HOLD_S = (0.5, 3.0)
PAUSE_S = (0.2, 1.0)  # between two jogs
QUICK_STOP_SHARE = 0.15
FALLING_RPM = 5.0  # slower by at least this over half a second: still ramping down
RAMP_MAX_S = 30.0  # no ramp-down takes longer on these drives (6000 rpm at the lowest decel)
SETTLE_S = 5.0  # the axis comes to rest (|v| < STILL_RPM) within this after a jog, or it runs
STILL_RPM = 30.0
RSS_TARGET_MB = 20.0
TARGET_MINUTES = 30.0
RSS_SAMPLE_S = 5.0
REPORT_S = 60.0
USER_STOP = "stopped by the user"
QUICK_STOP = "quick stop"


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


def percentile(values: list[float], q: float) -> float:
    if not values:
        return float("nan")
    return float(np.percentile(values, q))


def rss_mb() -> float:
    return float(psutil.Process().memory_info().rss) / MB


def verdict(ok: bool) -> str:
    return "PASS" if ok else "MISS"


# ---------------------------------------------------------------------- the browser (child)


@dataclass
class LoadReport:
    latencies_ms: dict[str, list[float]] = field(default_factory=dict)
    requests: collections.Counter[str] = field(default_factory=collections.Counter)
    errors: collections.Counter[str] = field(default_factory=collections.Counter)  # "route status"
    error_notes: list[str] = field(default_factory=list)
    jog_stops: collections.Counter[str] = field(default_factory=collections.Counter)  # by reason
    jogs: collections.Counter[str] = field(default_factory=collections.Counter)  # "node n mode"
    quick_stops: int = 0
    quick_stop_reasons: collections.Counter[str] = field(default_factory=collections.Counter)
    fault_resets: int = 0
    # the axis still moving SETTLE_S after a jog ended, or after an enable: "node n mode, when"
    runaways: collections.Counter[str] = field(default_factory=collections.Counter)
    notes: list[str] = field(default_factory=list)


class Load:
    """What the browser did, shared by its threads."""

    def __init__(self) -> None:
        self.report = LoadReport()
        self.lock = threading.Lock()

    def call(
        self,
        label: str,
        send: Callable[[], httpx.Response],
        expected: tuple[int, ...] = (),
    ) -> httpx.Response | None:
        """Times one request; a 5xx, or a 4xx not in `expected`, or no answer is an error."""
        started = time.perf_counter()
        try:
            response = send()
        except httpx.HTTPError as exc:
            with self.lock:
                self.report.requests[label] += 1
                self.report.errors[f"{label} {type(exc).__name__}"] += 1
                self.report.error_notes.append(f"{label}: {type(exc).__name__}: {exc}"[:240])
            return None
        elapsed = (time.perf_counter() - started) * 1e3
        status = response.status_code
        with self.lock:
            self.report.requests[label] += 1
            self.report.latencies_ms.setdefault(label, []).append(elapsed)
            if status >= 400 and status not in expected:
                self.report.errors[f"{label} {status}"] += 1
                self.report.error_notes.append(f"{label}: {status} {response.text[:200]}")
        return response

    def snapshot(self) -> LoadReport:
        with self.lock:
            return copy.deepcopy(self.report)


@dataclass
class Focus:
    """The node the Drive page shows (the one last jogged) and the Faults page's node."""

    node: int = 1
    faults_turn: int = 0


def pacer(period: float, halt: threading.Event) -> Iterator[None]:
    """setInterval-like: a tick that finds the last one still running is skipped."""
    due = time.perf_counter()
    while not halt.is_set():
        yield
        due += period
        now = time.perf_counter()
        if now > due:
            due += period * ((now - due) // period + 1)
        halt.wait(due - now)


def poller(
    base: str,
    label: str,
    path: Callable[[], str],
    period: float,
    halt: threading.Event,
    load: Load,
) -> None:
    with httpx.Client(base_url=base, timeout=10, headers=CLIENT) as http:
        for _ in pacer(period, halt):
            load.call(label, lambda: http.get(path()))


class Jogger:
    def __init__(self, base: str, load: Load, focus: Focus, halt: threading.Event) -> None:
        self.http = httpx.Client(base_url=base, timeout=10, headers=CLIENT)
        self.load, self.focus, self.halt = load, focus, halt
        self.rng = random.Random()
        self.nodes: dict[int, dict[str, Any]] = {}  # node -> its drive state at the start

    def note(self, text: str) -> None:
        with self.load.lock:
            self.load.report.notes.append(text[:240])

    def server_stop(self, reason: str | None) -> None:
        with self.load.lock:
            self.load.report.jog_stops[reason or "unknown"] += 1

    def prepare(self) -> None:
        for node in NODES:
            for index, rev in SIM_LIMITS:
                path = f"/api/nodes/{node}/sdo/{index:04X}/0"
                self.load.call(
                    "PUT /api/nodes/{n}/sdo/{i}/{s}",
                    partial(self.http.put, path, json={"value": rev * COUNTS_PER_REV}),
                )
            answer = self.load.call(
                "GET /api/nodes/{n}/drive", partial(self.http.get, f"/api/nodes/{node}/drive")
            )
            if answer is None or answer.status_code != 200:
                continue
            state = answer.json()
            if {"pv", "pt"} & set(state["supported_modes"]):
                self.nodes[node] = state
        self.note(
            "jogging nodes: "
            + ", ".join(
                f"{n} ({'/'.join(m for m in ('pv', 'pt') if m in s['supported_modes'])},"
                f" ≤ {s['limits']['max_velocity_rpm']:g} rpm,"
                f" ≤ {s['limits']['max_torque_pct']:g} %)"
                for n, s in self.nodes.items()
            )
        )

    def drive(self, node: int) -> dict[str, Any] | None:
        answer = self.load.call(
            "GET /api/nodes/{n}/drive", lambda: self.http.get(f"/api/nodes/{node}/drive")
        )
        if answer is None or answer.status_code != 200:
            return None
        state: dict[str, Any] = answer.json()
        return state

    def enable(self, node: int) -> bool:
        state = self.drive(node)
        if state is None:
            return False
        faulted = state["state"] == "fault"
        if faulted:
            fault = state.get("fault") or {}
            self.note(
                f"node {node} in fault before a jog: {fault.get('code_hex')} {fault.get('name')}"
                f" at {state['position_inc'] / COUNTS_PER_REV:.1f} motor rev, inputs"
                f" {state['inputs']}"
            )
            with self.load.lock:
                self.load.report.fault_resets += 1
            self.load.call(
                "POST /api/nodes/{n}/drive/fault-reset",
                lambda: self.http.post(f"/api/nodes/{node}/drive/fault-reset"),
            )
        if state["state"] != "operation_enabled":
            answer = self.load.call(
                "POST /api/nodes/{n}/drive/enable",
                lambda: self.http.post(f"/api/nodes/{node}/drive/enable"),
            )
            if answer is not None and answer.status_code == 200:
                return True
            if faulted:
                self.note(f"node {node} stays in fault: no more jogs on it")
                self.nodes.pop(node, None)
            return False
        return True

    def settle(self, node: int, when: str) -> dict[str, Any] | None:
        """Waits for the axis to come to rest (it coasts after a jog); an axis still moving
        after SETTLE_S with no jog running is a runaway: reported, then stopped with a short
        jog and DELETE (whose stop zeroes the target)."""
        started = time.monotonic()
        deadline = started + SETTLE_S
        last_speed = float("inf")
        while True:
            state = self.drive(node)
            if state is None or abs(state["velocity_rpm"]) < STILL_RPM:
                return state
            speed = abs(state["velocity_rpm"])
            # past SETTLE_S, an axis still ramping down (a low profile deceleration after a
            # fast jog) is not a runaway: only one whose speed stops falling is
            falling = speed < last_speed - FALLING_RPM
            if self.halt.is_set() or time.monotonic() - started > RAMP_MAX_S:
                break
            if time.monotonic() > deadline and not falling:
                break
            if time.monotonic() > deadline:
                deadline = time.monotonic() + 0.5  # judge the next half second
                last_speed = speed
            self.halt.wait(0.2)
        mode = state["mode"]
        self.note(
            f"node {node} runaway {when}: {state['state']}, mode {mode},"
            f" {state['velocity_rpm']:.0f} rpm at {state['position_inc'] / COUNTS_PER_REV:.1f}"
            f" motor rev, {SETTLE_S:.0f} s on"
        )
        with self.load.lock:
            self.load.report.runaways[f"node {node} {mode}, {when}"] += 1
        sign = -1.0 if state["velocity_rpm"] > 0 else 1.0
        body = {"mode": "pv", "velocity_rpm": sign * 10.0, "keepalive_ms": KEEPALIVE_MS}
        answer = self.load.call(
            "POST /api/nodes/{n}/jog", lambda: self.http.post(f"/api/nodes/{node}/jog", json=body)
        )
        if answer is not None and answer.status_code == 200:
            jog_id = answer.json()["jog_id"]
            self.load.call("DELETE /api/jog/{id}", lambda: self.http.delete(f"/api/jog/{jog_id}"))
        self.halt.wait(1.0)
        return self.drive(node)

    def one_jog(self) -> None:
        node = self.rng.choice(sorted(self.nodes))
        self.focus.node = node
        info = self.nodes[node]
        modes = [m for m in ("pv", "pt") if m in info["supported_modes"]]
        mode = self.rng.choice(modes)
        if not self.enable(node):
            return
        state = self.settle(node, "before a jog (after the last jog on it and an enable)")
        if state is None:
            return
        position = state["position_inc"] / COUNTS_PER_REV  # motor revs, as 5FF1h/5FF2h
        if position > STEER_REV:
            sign = -1.0
        elif position < -STEER_REV:
            sign = 1.0
        else:
            sign = self.rng.choice((-1.0, 1.0))
        limits = info["limits"]
        body: dict[str, Any] = {"mode": mode, "keepalive_ms": KEEPALIVE_MS}
        if mode == "pv":
            body["velocity_rpm"] = sign * self.rng.uniform(10.0, limits["max_velocity_rpm"])
        else:
            top = min(limits["max_torque_pct"], PT_TORQUE_CAP)
            body["torque_pct"] = sign * self.rng.uniform(5.0, top)
        answer = self.load.call(
            "POST /api/nodes/{n}/jog", lambda: self.http.post(f"/api/nodes/{node}/jog", json=body)
        )
        if answer is None or answer.status_code != 200:
            return
        with self.load.lock:
            self.load.report.jogs[f"node {node} {mode}"] += 1
        jog_id = answer.json()["jog_id"]
        hold = self.rng.uniform(*HOLD_S)
        quick = self.rng.random() < QUICK_STOP_SHARE
        ends = time.perf_counter() + hold
        for _ in pacer(KEEPALIVE_S, self.halt):
            if time.perf_counter() >= ends:
                break
            beat = self.load.call(
                "POST /api/jog/{id}/keepalive",
                lambda: self.http.post(f"/api/jog/{jog_id}/keepalive"),
                expected=(409,),
            )
            if beat is not None and beat.status_code == 409:
                reason = (beat.json().get("jog") or {}).get("stop_reason")
                self.server_stop(reason)
                self.note(f"node {node} {mode} jog stopped by the server: {reason}")
                return
        if quick:
            self.load.call(
                "POST /api/nodes/{n}/drive/quick-stop",
                lambda: self.http.post(f"/api/nodes/{node}/drive/quick-stop"),
            )
            after = self.load.call("GET /api/jog/{id}", lambda: self.http.get(f"/api/jog/{jog_id}"))
            reason = None if after is None else after.json().get("stop_reason")
            with self.load.lock:
                self.load.report.quick_stops += 1
                self.load.report.quick_stop_reasons[str(reason)] += 1
            if reason != QUICK_STOP:
                self.note(f"node {node} quick stop: the jog's stop reason is {reason!r}")
            if self.enable(node):
                self.halt.wait(1.0)
                self.settle(node, f"{mode}: enabled again after a quick stop, no jog running")
            return
        stop = self.load.call(
            "DELETE /api/jog/{id}", lambda: self.http.delete(f"/api/jog/{jog_id}")
        )
        if stop is not None and stop.status_code == 200:
            reason = stop.json().get("stop_reason")
            if reason != USER_STOP:  # it had stopped before we let go
                self.server_stop(reason)
                self.note(f"node {node} {mode} jog had stopped before DELETE: {reason}")

    def run(self) -> None:
        try:
            self.prepare()
            while not self.halt.is_set() and self.nodes:
                self.one_jog()
                self.halt.wait(self.rng.uniform(*PAUSE_S))
            for node in self.nodes:
                self.load.call(
                    "POST /api/nodes/{n}/drive/disable",
                    partial(self.http.post, f"/api/nodes/{node}/drive/disable"),
                )
                self.load.call(
                    "DELETE /api/nodes/{n}/drive/controller",
                    partial(self.http.delete, f"/api/nodes/{node}/drive/controller"),
                )
        except Exception as exc:  # reported, not raised in a daemon thread
            self.note(f"jogger crashed: {type(exc).__name__}: {exc}")
        finally:
            self.http.close()


def page_polls(focus: Focus, capture_id: int | None) -> list[tuple[str, Callable[[], str], float]]:
    """What the pages poll (label, path, period s): the Drive page of `focus.node`, the Faults
    page of each node in turn, the Scope page's capture unless `capture_id` is None."""

    def faults_path() -> str:
        focus.faults_turn += 1
        return f"/api/nodes/{NODES[focus.faults_turn % len(NODES)]}/faults"

    polls: list[tuple[str, Callable[[], str], float]] = [
        ("GET /api/nodes/{n}/drive", lambda: f"/api/nodes/{focus.node}/drive", 0.200),
        (
            "GET /api/nodes/{n}/drive/controller",
            lambda: f"/api/nodes/{focus.node}/drive/controller",
            2.0,
        ),
        ("GET /api/scope/captures/{id}", lambda: f"/api/scope/captures/{capture_id}", 0.250),
        ("GET /api/nodes/{n}/faults", faults_path, 2.0),
        ("GET /api/nodes", lambda: "/api/nodes", 3.0),
        ("GET /api/bus", lambda: "/api/bus", 3.0),
        ("GET /api/events", lambda: "/api/events?limit=100", 3.0),
    ]
    if capture_id is None:
        polls = [poll for poll in polls if "captures" not in poll[0]]
    return polls


def browser(base: str, capture_id: int | None, up: Queue[Any], down: Queue[Any]) -> None:
    """Child process: polls and jogs; answers "snap" with a LoadReport, "stop" stops it."""
    load = Load()
    focus = Focus()
    halt = threading.Event()
    polls = page_polls(focus, capture_id)
    threads = [
        threading.Thread(target=poller, args=(base, *poll, halt, load), daemon=True)
        for poll in polls
    ]
    jogger = Jogger(base, load, focus, halt)
    threads.append(threading.Thread(target=jogger.run, daemon=True))
    for thread in threads:
        thread.start()
    up.put("started")
    while True:
        command = down.get()
        if command == "stop":
            halt.set()
            for thread in threads:
                thread.join(30)
            up.put(load.snapshot())
            return
        up.put(load.snapshot())


# ---------------------------------------------------------------------- the app


@contextmanager
def serve_app(settings: Settings) -> Iterator[tuple[str, FastAPI]]:
    """The app on uvicorn in a thread (as tests/live_server.py), with its nodes scanned."""
    import uvicorn

    from servodesk.app import create_app

    app = create_app(settings, static_dir=None)
    config = uvicorn.Config(app, host="127.0.0.1", port=settings.port, log_level="warning")
    server = uvicorn.Server(config)
    thread = threading.Thread(target=server.run, name="live-server", daemon=True)
    thread.start()
    deadline = time.monotonic() + 30
    while not server.started:
        if time.monotonic() > deadline or not thread.is_alive():
            raise RuntimeError("the app did not start")
        time.sleep(0.05)
    base = f"http://127.0.0.1:{settings.port}"
    try:
        while True:
            nodes = {n["node"] for n in httpx.get(f"{base}/api/nodes", timeout=10).json()}
            if set(NODES) <= nodes:
                break
            if time.monotonic() > deadline:
                raise RuntimeError(f"the start-up scan found nodes {sorted(nodes)}")
            time.sleep(0.1)
        yield base, app
    finally:
        server.should_exit = True
        thread.join(timeout=30)


def start_capture(http: httpx.Client, duration: float) -> dict[str, Any]:
    body = {"signals": SIGNALS, "sync_period_us": PERIOD_US, "duration_s": duration}
    deadline = time.monotonic() + 15
    while True:
        response = http.post("/api/scope/captures", json=body)
        if response.status_code == 200:
            capture: dict[str, Any] = response.json()
            return capture
        if time.monotonic() > deadline:
            raise RuntimeError(f"the capture did not start: {response.status_code} {response.text}")
        time.sleep(0.5)


# ---------------------------------------------------------------------- report


@dataclass
class Soak:
    started: float  # monotonic
    rss: list[tuple[float, float]]  # (s since start, MB)
    stats0: SimBusStats


def trend_mb_min(rss: list[tuple[float, float]], skip_s: float) -> float:
    points = [(t, m) for t, m in rss if t >= skip_s]
    if len(points) < 3:
        return float("nan")
    t, m = np.array(points).T
    return float(np.polyfit(t, m, 1)[0]) * 60


def capture_line(capture: dict[str, Any]) -> str:
    began = capture.get("trigger_time") or capture.get("started")
    if began is None:
        return f"capture {capture['id']}: {capture['state']}, not started"
    end = capture.get("ended") or time.time()
    per_signal = (end - began) * 1e6 / PERIOD_US
    expected = per_signal * len(capture["signals"])
    got = capture["samples"]
    return (
        f"capture {capture['id']} {capture['state']}: samples {got:,} of ~{expected:,.0f} expected"
        f" ({100 * got / max(expected, 1):.1f} %, {len(capture['signals'])} signals × 1 kHz ×"
        f" {end - began:.1f} s; the app flushes every 33 ms), lost {capture['lost']}"
    )


def runner_line(before: SimBusStats, after: SimBusStats) -> str:
    return (
        f"sim runner: ticks {after.ticks - before.ticks}, overruns"
        f" {after.overruns - before.overruns} (since the app started {after.overruns}), worst"
        f" tick lateness {after.max_lateness * 1e3:.1f} ms since the app started; send errors"
        f" {after.send_errors - before.send_errors}, node errors"
        f" {after.node_errors - before.node_errors}"
    )


def print_load(report: LoadReport, *, full: bool) -> None:
    total = sum(report.requests.values())
    errors = sum(report.errors.values())
    print(f"requests {total:,}, errors {errors}")
    for key, n in sorted(report.errors.items()):
        print(f"  error: {key}: {n}")
    for text in report.error_notes[:8]:
        print(f"    {text}")
    jogs = sum(report.jogs.values())
    stops = sum(report.jog_stops.values())
    print(
        f"jogs {jogs} ({', '.join(f'{k} {v}' for k, v in sorted(report.jogs.items()))});"
        f" quick stops {report.quick_stops} (jog stop reasons:"
        f" {dict(report.quick_stop_reasons)}); fault resets {report.fault_resets}"
    )
    runaways = sum(report.runaways.values())
    print(
        f"runaways (axis moving {SETTLE_S:.0f} s after and not slowing, no jog running): {runaways}"
        + "".join(f"\n  {n} × {key}" for key, n in report.runaways.most_common())
    )
    print(
        f"jogs stopped by the server (not errors): {stops}"
        + "".join(f"\n  {n} × {reason}" for reason, n in report.jog_stops.most_common())
    )
    print(
        "API latency ms since the start (p50 / p99 / max, requests):"
        if full
        else "API latency ms since the start (p50 / p99 / max, requests), busiest routes:"
    )
    labels = sorted(report.latencies_ms, key=lambda k: -len(report.latencies_ms[k]))
    for label in labels if full else labels[:5]:
        values = report.latencies_ms[label]
        print(
            f"  {label:<40} {percentile(values, 50):7.1f} {percentile(values, 99):7.1f}"
            f" {max(values):7.1f}  n {len(values):6d}"
        )
    if full:
        for text in report.notes[:20]:
            print(f"  note: {text}")
        if len(report.notes) > 20:
            print(f"  … {len(report.notes) - 20} more notes")


def status(
    title: str,
    soak: Soak,
    http: httpx.Client,
    capture_id: int | None,
    stats: Callable[[], SimBusStats],
    report: LoadReport | None,
    *,
    full: bool = False,
) -> dict[str, Any]:
    elapsed = time.monotonic() - soak.started
    rss = rss_mb()
    capture: dict[str, Any] = {"state": "none", "lost": 0}
    growth = rss - soak.rss[0][1]
    print(f"\n== {title}, {elapsed:.0f} s ==")
    print(f"app process RSS {rss:.1f} MB ({growth:+.1f} MB since the start)")
    if capture_id is None:
        print("no capture (--no-capture)")
    else:
        capture = http.get(f"/api/scope/captures/{capture_id}").json()
        print(capture_line(capture))
    print(runner_line(soak.stats0, stats()))
    if report is not None:
        print_load(report, full=full)
    return capture


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--duration", type=float, default=120.0, help="s (1800: 30 minutes)")
    parser.add_argument(
        "--no-capture", action="store_true", help="diagnosis: no scope capture (RSS without it)"
    )
    parser.add_argument("--seed", type=int, default=None, help="random seed of the main process")
    args = parser.parse_args()
    if args.seed is not None:
        random.seed(args.seed)
    from servodesk.settings import Settings

    print(
        f"soak {args.duration:.0f} s: app in this process (uvicorn in a thread, simulated drives"
        f" {', '.join(map(str, NODES))}), browser load in a child process;"
        f" {psutil.cpu_count()} CPUs, load average"
        f" {' '.join(f'{x:.1f}' for x in psutil.getloadavg())}"
    )
    process_start_rss = rss_mb()
    with tempfile.TemporaryDirectory(prefix="servodesk-soak-") as tmp:
        settings = Settings(
            simulated=True, scope_live_view=False, data_dir=Path(tmp), port=free_port()
        )
        with serve_app(settings) as (base, app):
            sim = app.state.services.bus.sim

            def stats() -> SimBusStats:
                result: SimBusStats = sim.stats
                return result

            http = httpx.Client(base_url=base, timeout=30)
            capture_s = min(args.duration + 60.0, 3600.0)
            capture = None if args.no_capture else start_capture(http, capture_s)
            capture_id = None if capture is None else int(capture["id"])
            ctx = multiprocessing.get_context("spawn")
            up: Queue[Any] = ctx.Queue()
            down: Queue[Any] = ctx.Queue()
            child = ctx.Process(target=browser, args=(base, capture_id, up, down), daemon=True)
            child.start()
            up.get(timeout=60)
            soak = Soak(time.monotonic(), [(0.0, rss_mb())], stats())
            print(f"RSS before the app {process_start_rss:.1f} MB")
            if capture is not None:
                names = ", ".join(
                    f"{s['node']}:{s['index']:04X}h ({s['source']})" for s in capture["signals"]
                )
                print(f"capture {capture_id} for up to {capture_s:.0f} s: {names}")
            status("start", soak, http, capture_id, stats, None)
            next_report = REPORT_S
            end = args.duration
            while True:
                elapsed = time.monotonic() - soak.started
                if elapsed >= end:
                    break
                time.sleep(min(RSS_SAMPLE_S, end - elapsed, max(0.0, next_report - elapsed)))
                elapsed = time.monotonic() - soak.started
                soak.rss.append((elapsed, rss_mb()))
                if elapsed >= next_report and elapsed < end - 1:
                    down.put("snap")
                    status(f"minute {elapsed / 60:.0f}", soak, http, capture_id, stats, up.get())
                    next_report += REPORT_S
            down.put("stop")
            report: LoadReport = up.get(timeout=120)
            child.join(10)
            soak.rss.append((time.monotonic() - soak.started, rss_mb()))
            if capture_id is not None:
                stopped = http.delete(f"/api/scope/captures/{capture_id}")
                if stopped.status_code >= 400:
                    print(f"stopping the capture: {stopped.status_code} {stopped.text[:200]}")
            final = status("end", soak, http, capture_id, stats, report, full=True)
            http.close()
    summary(args.duration, soak, report, final)


def summary(duration: float, soak: Soak, report: LoadReport, capture: dict[str, Any]) -> None:
    start = soak.rss[0][1]
    growth = soak.rss[-1][1] - start
    skip = min(60.0, duration * 0.2)  # start-up: allocator and caches warming
    trend = trend_mb_min(soak.rss, skip)
    peak = max(m for _, m in soak.rss)
    samples = ", ".join(f"{t:.0f} s {m:.0f}" for t, m in soak.rss[:: max(1, len(soak.rss) // 12)])
    print("\n== verdict ==")
    print(f"RSS MB over time: {samples}; peak {peak:.1f}")
    projected = trend * TARGET_MINUTES
    print(
        f"RSS growth {growth:+.1f} MB in {duration / 60:.1f} min"
        f" ({growth / max(duration / 60, 1e-9):+.2f} MB/min); linear-fit trend after {skip:.0f} s"
        f" {trend:+.2f} MB/min → {projected:+.1f} MB in {TARGET_MINUTES:.0f} min"
    )
    ok_growth = growth <= RSS_TARGET_MB
    ok_trend = not projected > RSS_TARGET_MB  # nan (too few samples) passes on growth alone
    print(
        f"  growth {growth:+.1f} MB / target ≤ {RSS_TARGET_MB:.0f} MB (for {TARGET_MINUTES:.0f}"
        f" min): ratio {max(growth, 0.0) / RSS_TARGET_MB:.2f} → {verdict(ok_growth)}"
    )
    print(
        f"  trend extrapolated to {TARGET_MINUTES:.0f} min {projected:+.1f} MB / target ≤"
        f" {RSS_TARGET_MB:.0f} MB: ratio {max(projected, 0.0) / RSS_TARGET_MB:.2f} →"
        f" {verdict(ok_trend)}"
    )
    errors = sum(report.errors.values())
    print(
        f"  errors {errors} / target 0 → {verdict(errors == 0)}"
        f" ({sum(report.requests.values()):,} requests; jogs stopped by the server:"
        f" {sum(report.jog_stops.values())}, reported above, not counted as errors)"
    )
    runaways = sum(report.runaways.values())
    print(
        f"  runaways (motion with no jog running) {runaways} / target 0 → {verdict(runaways == 0)}"
    )
    print(
        f"  capture lost {capture['lost']} / target 0 → {verdict(capture['lost'] == 0)};"
        f" state {capture['state']}"
    )


if __name__ == "__main__":
    main()
