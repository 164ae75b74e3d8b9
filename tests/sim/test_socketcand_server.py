"""SocketcandServer: python-can's `socketcand` client joins a SimBus over loopback TCP."""

from __future__ import annotations

import os
import selectors
import signal
import socket
import subprocess
import sys
import time
import uuid
from collections.abc import Callable, Iterator

import can
import canopen
import pytest

import servodesk_data
from servodesk_sim.frames import Frame, frame
from servodesk_sim.runner import SimBus, SimNode
from servodesk_sim.socketcand_server import (
    BadMessageError,
    SocketcandServer,
    format_frame,
    is_loopback,
    parse_send,
)

WAIT = 2.0  # s: upper bound for anything to arrive; tests never assert how fast


class EchoNode:
    """Answers 0x600+id on 0x580+id with the same bytes (an SDO server's shape, no meaning)."""

    def __init__(self, node_id: int) -> None:
        self._node_id = node_id

    @property
    def node_id(self) -> int:
        return self._node_id

    def boot(self, now: float) -> list[Frame]:
        return [Frame(0x700 + self._node_id, b"\x00")]

    def on_frame(self, f: Frame, now: float) -> list[Frame]:
        if f.can_id == 0x600 + self._node_id and not f.rtr:
            return [Frame(0x580 + self._node_id, f.data)]
        return []

    def poll(self, now: float) -> list[Frame]:
        return []


class ChattyNode(EchoNode):
    """Sends a frame on every tick, so the bus is never quiet during a handshake."""

    def __init__(self, node_id: int) -> None:
        super().__init__(node_id)
        self.count = 0

    def poll(self, now: float) -> list[Frame]:
        self.count += 1
        return [Frame(0x180 + self.node_id, self.count.to_bytes(4, "little"))]


@pytest.fixture
def channel() -> str:
    return f"test-socketcand-{uuid.uuid4().hex}"


@pytest.fixture
def master(channel: str) -> Iterator[can.BusABC]:
    """Another instance on the in-process virtual bus (where the backend would sit)."""
    bus = can.Bus(interface="virtual", channel=channel)
    yield bus
    bus.shutdown()


@pytest.fixture
def serve(
    channel: str, master: can.BusABC
) -> Iterator[Callable[[list[SimNode]], tuple[SimBus, SocketcandServer]]]:
    """Start nodes on the virtual bus and serve them on an ephemeral loopback port."""
    started: list[tuple[can.BusABC, SimBus, SocketcandServer]] = []

    def start(nodes: list[SimNode]) -> tuple[SimBus, SocketcandServer]:
        bus = can.Bus(interface="virtual", channel=channel)
        sim = SimBus(bus, nodes)
        sim.start()
        server = SocketcandServer(sim, port=0)
        server.start()
        started.append((bus, sim, server))
        return sim, server

    yield start
    for bus, sim, server in started:
        server.stop()
        sim.stop()
        bus.shutdown()


@pytest.fixture
def clients() -> Iterator[Callable[[SocketcandServer], can.BusABC]]:
    opened: list[can.BusABC] = []

    def connect(server: SocketcandServer) -> can.BusABC:
        host, port = server.address
        bus = can.Bus(interface="socketcand", host=host, port=port, channel="can0")
        opened.append(bus)
        return bus

    yield connect
    for bus in opened:
        bus.shutdown()


def recv_frame(bus: can.BusABC, can_id: int, timeout: float = WAIT) -> can.Message:
    deadline = time.monotonic() + timeout
    while (left := deadline - time.monotonic()) > 0:
        msg = bus.recv(left)
        if msg is not None and msg.arbitration_id == can_id:
            return msg
    pytest.fail(f"no frame {can_id:03X} within {timeout} s")


def recv_ids(bus: can.BusABC, timeout: float) -> list[int]:
    """Every frame id that arrives within `timeout` (for "this did not arrive" checks)."""
    ids: list[int] = []
    deadline = time.monotonic() + timeout
    while (left := deadline - time.monotonic()) > 0:
        msg = bus.recv(left)
        if msg is not None:
            ids.append(msg.arbitration_id)
    return ids


def msg(can_id: int, hex_bytes: str = "") -> can.Message:
    return can.Message(arbitration_id=can_id, data=bytes.fromhex(hex_bytes), is_extended_id=False)


def wait_for(condition: Callable[[], bool], timeout: float = WAIT) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            pytest.fail("condition not met in time")
        time.sleep(0.005)


class RawClient:
    """A bare TCP client for what python-can's client never sends."""

    def __init__(self, server: SocketcandServer) -> None:
        self.sock = socket.create_connection(server.address, timeout=WAIT)
        self.buf = b""

    def expect(self, message: bytes) -> None:
        while len(self.buf) < len(message):
            chunk = self.sock.recv(256)
            if not chunk:
                pytest.fail(f"connection closed while waiting for {message!r}")
            self.buf += chunk
        got, self.buf = self.buf[: len(message)], self.buf[len(message) :]
        assert got == message

    def handshake(self) -> None:
        self.expect(b"< hi >")
        self.sock.sendall(b"< open can0 >")
        self.expect(b"< ok >")
        self.sock.sendall(b"< rawmode >")
        self.expect(b"< ok >")


# --------------------------------------------------------------------------- pure parts


@pytest.mark.parametrize(
    ("f", "timestamp", "line"),
    [
        (frame(0x584, "43 00 10 00 92 01 02 00"), 1.5, b"< frame 584 1.500000 4300100092010200 >"),
        (frame(0x080), 1700000000.000123, b"< frame 080 1700000000.000123  >"),
        (frame(0x7FF, "0A"), 2.9999999, b"< frame 7FF 2.999999 0A >"),
    ],
)
def test_format_frame(f: Frame, timestamp: float, line: bytes) -> None:
    assert format_frame(f, timestamp) == line


def test_python_can_parses_what_the_server_sends() -> None:
    from can.interfaces.socketcand.socketcand import convert_ascii_message_to_can_message

    for f in (frame(0x584, "4B 41 60 00 37 02 00 00"), frame(0x000, "01 00"), frame(0x080)):
        parsed = convert_ascii_message_to_can_message(format_frame(f, 12.25).decode())
        assert parsed is not None
        assert (parsed.arbitration_id, bytes(parsed.data), parsed.is_extended_id) == (
            f.can_id,
            f.data,
            False,
        )
        assert parsed.timestamp == 12.25


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("send 604 8 40 0 10 0 0 0 0 0", frame(0x604, "40 00 10 00 00 00 00 00")),  # python-can
        ("send 000 2 1 4", frame(0x000, "01 04")),
        ("send 080 0", frame(0x080)),
        ("send 704 1", None),  # python-can's rendering of a remote frame: no data
        ("send 00000604 1 40", None),  # extended id
        ("send 800 1 40", None),  # beyond 11 bits
    ],
)
def test_parse_send(text: str, expected: Frame | None) -> None:
    assert parse_send(text.split()) == expected


@pytest.mark.parametrize(
    "text",
    [
        "send",
        "send 604",
        "send 60g 1 40",
        "send 604 9 1 2 3 4 5 6 7 8 9",
        "send 604 2 40",
        "send 604 1 400",
        "send 604 1 -1",
    ],
)
def test_parse_send_rejects_malformed(text: str) -> None:
    with pytest.raises(BadMessageError):
        parse_send(text.split())


@pytest.mark.parametrize(
    ("host", "loopback"),
    [
        ("127.0.0.1", True),
        ("127.1.2.3", True),
        ("::1", True),
        ("[::1]", True),
        ("localhost", True),
        ("0.0.0.0", False),
        ("192.168.1.10", False),
        ("example.com", False),
    ],
)
def test_is_loopback(host: str, loopback: bool) -> None:
    assert is_loopback(host) is loopback


def test_non_loopback_hosts_are_refused_unless_allowed(channel: str) -> None:
    bus = can.Bus(interface="virtual", channel=channel)
    try:
        sim = SimBus(bus, [])
        with pytest.raises(ValueError, match="not a loopback address"):
            SocketcandServer(sim, host="0.0.0.0")
        SocketcandServer(sim, host="0.0.0.0", allow_remote=True).stop()  # constructed, unstarted
    finally:
        bus.shutdown()


# --------------------------------------------------------------------------- over TCP


def test_a_client_exchanges_frames_with_a_node_and_the_virtual_bus(
    serve: Callable[[list[SimNode]], tuple[SimBus, SocketcandServer]],
    clients: Callable[[SocketcandServer], can.BusABC],
    master: can.BusABC,
) -> None:
    _sim, server = serve([EchoNode(4)])
    client = clients(server)
    client.send(msg(0x604, "40 00 10 00 00 00 00 00"))
    answer = recv_frame(client, 0x584)
    assert bytes(answer.data) == bytes.fromhex("40 00 10 00 00 00 00 00")
    assert not answer.is_extended_id
    # the client's request and the answer are on the in-process bus too
    assert bytes(recv_frame(master, 0x604).data) == bytes.fromhex("40 00 10 00 00 00 00 00")
    assert bytes(recv_frame(master, 0x584).data) == bytes.fromhex("40 00 10 00 00 00 00 00")
    # and what the in-process master sends reaches the client
    master.send(msg(0x000, "01 00"))
    assert bytes(recv_frame(client, 0x000).data) == b"\x01\x00"


def test_two_clients_see_each_others_frames_but_not_their_own(
    serve: Callable[[list[SimNode]], tuple[SimBus, SocketcandServer]],
    clients: Callable[[SocketcandServer], can.BusABC],
) -> None:
    _sim, server = serve([EchoNode(4)])
    a, b = clients(server), clients(server)
    a.send(msg(0x123, "AA"))
    assert bytes(recv_frame(b, 0x123).data) == b"\xaa"
    b.send(msg(0x321, "BB"))
    assert bytes(recv_frame(a, 0x321).data) == b"\xbb"
    assert 0x123 not in recv_ids(a, 0.1)
    assert 0x321 not in recv_ids(b, 0.1)


def test_a_client_leaving_does_not_disturb_the_others(
    serve: Callable[[list[SimNode]], tuple[SimBus, SocketcandServer]],
    clients: Callable[[SocketcandServer], can.BusABC],
) -> None:
    _sim, server = serve([EchoNode(4)])
    leaver, stayer = clients(server), clients(server)
    leaver.send(msg(0x604, "01"))
    recv_frame(stayer, 0x584)
    leaver.shutdown()
    wait_for(lambda: server.client_count == 1)
    stayer.send(msg(0x604, "02"))
    assert bytes(recv_frame(stayer, 0x584).data) == b"\x02"


def test_handshake_survives_a_busy_bus_and_listeners_get_frames(
    serve: Callable[[list[SimNode]], tuple[SimBus, SocketcandServer]],
    clients: Callable[[SocketcandServer], can.BusABC],
) -> None:
    # A frame glued to `< ok >` would make python-can's constructor raise CanError.
    _sim, server = serve([ChattyNode(4)])
    for _ in range(3):
        listener = clients(server)  # never sends: forwarding starts after the grace period
        first = recv_frame(listener, 0x184)
        assert len(first.data) == 4


def test_no_frame_is_glued_to_the_rawmode_reply(
    serve: Callable[[list[SimNode]], tuple[SimBus, SocketcandServer]],
) -> None:
    # python-can compares ONE recv() with "< ok >": a client that reads the reply late must
    # still get it alone, even though the node sends a frame every millisecond meanwhile.
    _sim, server = serve([ChattyNode(4)])
    raw = RawClient(server)
    try:
        raw.expect(b"< hi >")
        raw.sock.sendall(b"< open can0 >")
        raw.expect(b"< ok >")
        raw.sock.sendall(b"< rawmode >")
        time.sleep(0.03)  # a slow reader; ~30 frames are due on the bus by now
        assert raw.sock.recv(256) == b"< ok >"
        raw.expect(b"< frame 184 ")  # ...and they follow once the grace period is over
    finally:
        raw.sock.close()


def test_remote_frames_are_not_forwarded(
    serve: Callable[[list[SimNode]], tuple[SimBus, SocketcandServer]],
    clients: Callable[[SocketcandServer], can.BusABC],
) -> None:
    sim, server = serve([EchoNode(4)])
    client = clients(server)
    client.send(msg(0x604, "01"))  # opens forwarding at once
    recv_frame(client, 0x584)
    sim.inject(Frame(0x704, rtr=True, dlc=1))
    sim.inject(frame(0x123, "01"))  # marker after the remote frame
    ids = []
    while (m := client.recv(WAIT)) is not None and m.arbitration_id != 0x123:
        ids.append(m.arbitration_id)
    assert m is not None
    assert 0x704 not in ids


def test_malformed_input_is_skipped_and_the_client_keeps_working(
    serve: Callable[[list[SimNode]], tuple[SimBus, SocketcandServer]], master: can.BusABC
) -> None:
    _sim, server = serve([EchoNode(4)])
    raw = RawClient(server)
    try:
        raw.handshake()
        raw.sock.sendall(b"garbage < send 12x 1 0 > < bogus > <  > < send 123 1 ff >")
        assert bytes(recv_frame(master, 0x123).data) == b"\xff"
        master.send(msg(0x321, "01 02"))
        raw.expect(b"< frame 321 ")  # still served after the bad input
        assert server.client_count == 1
    finally:
        raw.sock.close()


def test_a_client_flooding_garbage_is_closed_alone(
    serve: Callable[[list[SimNode]], tuple[SimBus, SocketcandServer]],
    clients: Callable[[SocketcandServer], can.BusABC],
) -> None:
    _sim, server = serve([EchoNode(4)])
    good = clients(server)
    raw = RawClient(server)
    try:
        raw.handshake()
        raw.sock.sendall(b"< nonsense >" * 100)
        raw.sock.settimeout(WAIT)
        while raw.sock.recv(4096):  # the server closes the connection: recv returns b""
            pass
    finally:
        raw.sock.close()
    good.send(msg(0x604, "03"))
    assert bytes(recv_frame(good, 0x584).data) == b"\x03"


def test_opening_another_channel_is_refused(
    serve: Callable[[list[SimNode]], tuple[SimBus, SocketcandServer]],
) -> None:
    # python-can raises CanError("Expected '< ok >' got: '< error … serving can0 >'") on this
    _sim, server = serve([EchoNode(4)])
    raw = RawClient(server)
    try:
        raw.expect(b"< hi >")
        raw.sock.sendall(b"< open vcan0 >")
        raw.expect(b"< error could not open bus, serving can0 >")
    finally:
        raw.sock.close()


def test_stop_disconnects_clients_and_frees_the_port(
    serve: Callable[[list[SimNode]], tuple[SimBus, SocketcandServer]],
) -> None:
    _sim, server = serve([EchoNode(4)])
    raw = RawClient(server)
    try:
        raw.handshake()
        server.stop()
        assert not server.running
        assert raw.sock.recv(256) == b""  # closed by the server
    finally:
        raw.sock.close()
    with socket.socket() as probe:
        # SO_REUSEADDR as servers use it: only a socket still listening blocks the bind
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        probe.bind(server.address)


# --------------------------------------------------------------------------- second process


# Stand-in drives for the CLI in a subprocess; the real ones replace them with `--node 4:mdi-s1c`.
def read_line_with(
    proc: subprocess.Popen[str], prefix: str, lines: list[str], timeout: float = 20.0
) -> str:
    """The first stdout line starting with `prefix`; every line read is added to `lines`.

    Read from the pipe itself, not through the text wrapper: its `readline()` may take two
    lines that came in one piece into its buffer, and the selector, which sees only the pipe,
    would then wait for the second one in vain (a busy host writes both before the test reads)."""
    assert proc.stdout is not None
    fd = proc.stdout.fileno()
    pending = ""
    deadline = time.monotonic() + timeout
    with selectors.DefaultSelector() as sel:
        sel.register(fd, selectors.EVENT_READ)
        while (left := deadline - time.monotonic()) > 0:
            if not sel.select(left):
                continue
            chunk = os.read(fd, 65536)
            if not chunk:
                pytest.fail(f"the simulator exited before printing {prefix!r}")
            *complete, pending = (pending + chunk.decode()).split("\n")
            for line in complete:
                lines.append(line + "\n")
            found = [line for line in complete if line.startswith(prefix)]
            if found:
                lines.append(pending)  # a line still being written: kept, not lost
                return found[0].strip()
    pytest.fail(f"no {prefix!r} line within {timeout} s")


def test_the_cli_serves_drives_to_another_process() -> None:
    """`servodesk-sim --serve` in its own process; python-canopen joins through python-can's
    socketcand interface and reads the MDi's device name with a segmented SDO upload."""
    command = [
        sys.executable,
        "-m",
        "servodesk_sim.cli",
        "--node",
        "4:mdi-s1c",
        "--node",
        "5:kinco",
        "--serve",
        "127.0.0.1:0",
    ]
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        lines: list[str] = []
        host_port = read_line_with(proc, "listening on ", lines).split()[2]
        host, port = host_port.rsplit(":", 1)
        network = canopen.Network()
        network.connect(interface="socketcand", host=host, port=int(port), channel="can0")
        try:
            mdi = network.add_node(4, str(servodesk_data.eds_path("mdi-s1c")))
            kinco = network.add_node(5, str(servodesk_data.eds_path("kinco")))
            assert mdi.sdo[0x1008].raw == "DVS_CANOPEN"
            assert mdi.sdo[0x2006][8].raw == 6000  # max speed (MDi-S1-C manual table 2.31)
            assert kinco.sdo[0x6041].raw & 0x4F == 0x40  # switch on disabled
        finally:
            network.disconnect()
        proc.send_signal(signal.SIGTERM)
        out, err = proc.communicate(timeout=20)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == 0, err
    assert "bus: Virtual bus channel servodesk (default;" in "".join(lines)
    assert "stopped: " in out  # the clean-shutdown summary, not a kill
