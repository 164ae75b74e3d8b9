"""What the web app adds on top of raw canopen, on the simulated drives.

The app runs with its three simulated drives (uvicorn on a free loopback port). A second
canopen.Network joins the same virtual bus, so both paths talk to the same drives in one run:

- read: median time of `GET /api/nodes/1/sdo/2006/08` (HTTP + service + SDO) against a raw
  `node.sdo.upload(0x2006, 8)` through canopen; prints both and the difference.
- upload all: entries per second of the app's "upload all" job on node 3 (the CiA 402 drive,
  the largest dictionary) against a raw canopen loop uploading the same readable entries.

Targets (issue: backend core): the API read adds <= 1 ms median; "upload all" reaches >= 0.9x
the raw loop's rate. Run: `make bench` or `.venv/bin/python bench/sdo_overhead.py`.
"""

from __future__ import annotations

import argparse
import socket
import statistics
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

import canopen
import httpx
import uvicorn
from fastapi import FastAPI

import servodesk_data
from servodesk.app import create_app
from servodesk.services import Services
from servodesk.settings import Settings


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


@contextmanager
def running_app() -> Iterator[tuple[str, FastAPI]]:
    port = free_port()
    app = create_app(Settings(simulated=True, port=port), static_dir=None)
    server = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=port, log_level="error"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    while not server.started:
        time.sleep(0.02)
    try:
        yield f"http://127.0.0.1:{port}", app
    finally:
        server.should_exit = True
        thread.join(10)


def median_ms(samples: list[float]) -> float:
    return statistics.median(samples) * 1e3


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--reads", type=int, default=300)
    args = parser.parse_args()
    with running_app() as (url, app):
        services: Services = app.state.services
        sim = services.bus.sim
        if sim is None:
            raise SystemExit("the app did not start its simulated drives")
        network = canopen.Network()
        network.connect(interface="virtual", channel=sim.bus.channel_info.split()[-1])
        try:
            raw1 = network.add_node(1, str(servodesk_data.eds_path("mdi-s1c")))
            raw3 = network.add_node(3, str(servodesk_data.eds_path("cia402")))
            with httpx.Client(base_url=url, timeout=10) as client:
                report_read(client, raw1, args.reads)
                report_upload_all(client, raw3)
        finally:
            network.disconnect()
    return 0


def report_read(client: httpx.Client, raw: canopen.RemoteNode, count: int) -> None:
    for _ in range(20):  # warm up both paths
        client.get("/api/nodes/1/sdo/2006/08").raise_for_status()
        raw.sdo.upload(0x2006, 8)
    api: list[float] = []
    direct: list[float] = []
    for _ in range(count):  # interleaved, so machine noise hits both alike
        start = time.perf_counter()
        client.get("/api/nodes/1/sdo/2006/08").raise_for_status()
        api.append(time.perf_counter() - start)
        start = time.perf_counter()
        raw.sdo.upload(0x2006, 8)
        direct.append(time.perf_counter() - start)
    added = median_ms(api) - median_ms(direct)
    print(
        f"read 2006h:08 x{count}: API median {median_ms(api):.3f} ms, "
        f"raw canopen median {median_ms(direct):.3f} ms"
    )
    print(f"API adds {added:.3f} ms median (target <= 1 ms: {added / 1.0:.2f}x of budget)")


def readable_entries(raw: canopen.RemoteNode) -> list[tuple[int, int]]:
    entries: list[tuple[int, int]] = []
    for index in sorted(raw.object_dictionary):
        obj = raw.object_dictionary[index]
        variables = [obj] if isinstance(obj, canopen.objectdictionary.ODVariable) else obj.values()
        entries += [(var.index, var.subindex) for var in variables if var.readable]
    return entries


def report_upload_all(client: httpx.Client, raw: canopen.RemoteNode) -> None:
    entries = readable_entries(raw)
    start = time.perf_counter()
    for index, sub in entries:
        try:
            raw.sdo.upload(index, sub)
        except canopen.SdoAbortedError:
            pass
    raw_rate = len(entries) / (time.perf_counter() - start)
    start = time.perf_counter()
    job = client.post("/api/nodes/3/upload-all").raise_for_status().json()
    while job["state"] == "running":
        time.sleep(0.005)
        job = client.get(f"/api/jobs/{job['id']}").raise_for_status().json()
    elapsed = time.perf_counter() - start
    api_rate = job["done"] / elapsed
    print(
        f"upload all node 3: raw loop {len(entries)} entries at {raw_rate:.0f}/s, "
        f"API job {job['done']} entries at {api_rate:.0f}/s ({job['state']})"
    )
    print(f"upload all rate ratio API/raw: {api_rate / raw_rate:.2f} (target >= 0.90)")


if __name__ == "__main__":
    raise SystemExit(main())
