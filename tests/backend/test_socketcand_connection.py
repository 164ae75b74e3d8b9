"""The app joins simulated drives served by `servodesk-sim --serve` through python-can's own
`socketcand` interface, as it joins a remote adapter."""

from __future__ import annotations

import socket
import uuid
from collections.abc import Iterator
from pathlib import Path

import can
import pytest
from fastapi.testclient import TestClient

from servodesk.app import create_app
from servodesk.bus.connection import default_bus_factory
from servodesk.models.bus import BusConfig
from servodesk.settings import Settings
from servodesk_sim.runner import run_drives
from servodesk_sim.socketcand_server import SocketcandServer


@pytest.fixture
def served_drives() -> Iterator[int]:
    bus = can.Bus(interface="virtual", channel=f"socketcand-{uuid.uuid4().hex}")
    sim = run_drives(bus, [(1, "mdi-s1c"), (3, "cia402")])
    server = SocketcandServer(sim, port=0)
    server.start()
    try:
        yield server.address[1]
    finally:
        server.stop()
        sim.stop()
        bus.shutdown()


def test_app_reaches_drives_through_socketcand(served_drives: int, tmp_path: Path) -> None:
    settings = Settings(
        interface="socketcand",
        channel="can0",
        bus_options={"host": "127.0.0.1", "port": served_drives},
        data_dir=tmp_path,
    )
    with TestClient(create_app(settings, static_dir=None)) as client:
        bus = client.get("/api/bus").json()
        assert (bus["state"], bus["interface"]) == ("connected", "socketcand")
        nodes = client.get("/api/nodes").json()
        assert [(n["node"], n["profile"]) for n in nodes] == [(1, "mdi-s1c"), (3, "cia402")]
        # a segmented upload across TCP
        assert client.get("/api/nodes/1/sdo/1008/0").json()["value"] == "DVS_CANOPEN"


@pytest.mark.parametrize(("options", "nagle_off"), [({}, True), ({"tcp_tune": False}, False)])
def test_socketcand_sends_each_frame_at_once(
    served_drives: int, options: dict[str, object], nagle_off: bool
) -> None:
    """Nagle's algorithm would hold a stop written while a SYNC waits for its ACK, up to the
    peer's delayed ACK (40 ms): ServoDesk turns it off unless the user's options say otherwise."""
    config = BusConfig(
        interface="socketcand",
        channel="can0",
        options={"host": "127.0.0.1", "port": served_drives, **options},
    )
    bus = default_bus_factory(config)
    try:
        sock: socket.socket = bus._SocketCanDaemonBus__socket  # type: ignore[attr-defined]
        assert bool(sock.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY)) is nagle_off
    finally:
        bus.shutdown()
