"""A loopback TCP endpoint speaking the socketcand protocol, so other processes join a SimBus.

Kernel vcan is not available here, and python-can's `socketcand` interface is the one client
every tool already has. No maintained Python socketcand *server* exists, so this is a small
hand-written one covering what python-can 4.6.1's client uses (can/interfaces/socketcand):

    server: < hi >
    client: < open CHANNEL >     server: < ok >
    client: < rawmode >          server: < ok >
    client: < send 123 2 a b >   server: < frame 123 1700000000.123456 0A0B >

Remote (RTR) frames and extended ids cannot take part: the protocol's raw mode has no RTR
flag, and the simulated segment is 11-bit CANopen. One thread serves every client with a
selector; frames reach it from the SimBus worker through per-client taps that only append to
a buffer and wake the selector.
"""

from __future__ import annotations

import contextlib
import ipaddress
import logging
import selectors
import socket
import threading
import time
from collections.abc import Callable
from enum import Enum

from servodesk_sim.frames import Frame
from servodesk_sim.runner import SimBus

log = logging.getLogger(__name__)

# python-can's client compares ONE recv() with "< ok >" after `rawmode`, so frames sent too
# early would arrive glued to that reply and fail its handshake. A client that sends anything
# has provably read the reply; a listen-only client (can.logger) never sends, so forwarding
# also starts this long after the reply. Frames tapped meanwhile wait in the client's buffer.
RAWMODE_GRACE = 0.25  # s
MAX_MESSAGE = 256  # chars of one `< … >` message; longer input is not socketcand
MAX_BUFFERED = 1 << 20  # bytes queued for one client before it is dropped as too slow
MAX_BAD_MESSAGES = 20  # malformed messages tolerated from one client before closing it
RECV_SIZE = 4096
QUICKACK: int | None = getattr(socket, "TCP_QUICKACK", None)  # Linux only


class ClientState(Enum):
    AWAIT_OPEN = "await_open"  # sent `< hi >`
    BCM = "bcm"  # bus opened; socketcand's default mode (we only support `send` in it)
    RAW = "raw"  # receives every frame on the bus


class BadMessageError(ValueError):
    """A client message that is not valid socketcand."""


def is_loopback(host: str) -> bool:
    """True for loopback addresses and `localhost`, which never reach the network."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


def format_frame(frame: Frame, timestamp: float) -> bytes:
    """`< frame ID SECONDS.USEC DATA >` as socketcand sends it (3 hex digits = standard id)."""
    seconds = int(timestamp)
    usec = min(round((timestamp - seconds) * 1e6), 999_999)
    # Empty data still needs its (empty) field: python-can splits on single spaces.
    return f"< frame {frame.can_id:03X} {seconds}.{usec:06d} {frame.data.hex().upper()} >".encode(
        "ascii"
    )


def parse_send(tokens: list[str]) -> Frame | None:
    """`send ID DLC B0 …` → Frame; None for frames this segment cannot carry (RTR, extended)."""
    if len(tokens) < 3:
        raise BadMessageError("send needs an id and a length")
    id_text, dlc_text, byte_texts = tokens[1], tokens[2], tokens[3:]
    try:
        can_id = int(id_text, 16)
        dlc = int(dlc_text, 16)
        data = bytes(int(b, 16) for b in byte_texts if len(b) <= 2)
    except ValueError as exc:
        raise BadMessageError(f"not hexadecimal: {exc}") from exc
    if len(data) != len(byte_texts):
        raise BadMessageError("data bytes must be 1-2 hex digits each")
    if not 0 <= dlc <= 8:
        raise BadMessageError(f"length {dlc} is not 0-8")
    if len(id_text) > 3 or can_id > 0x7FF:
        return None  # extended id: CANopen here uses 11-bit ids only
    if not data and dlc > 0:
        return None  # what python-can sends for a remote frame: no data, DLC only
    if len(data) != dlc:
        raise BadMessageError(f"length {dlc} but {len(data)} data bytes")
    return Frame(can_id, data)


class _Client:
    def __init__(self, sock: socket.socket, peer: str) -> None:
        self.sock = sock
        self.peer = peer
        self.state = ClientState.AWAIT_OPEN
        self.inbuf = bytearray()
        self.outbuf = bytearray()  # written by the server thread only
        self.frames = bytearray()  # filled by the tap (SimBus thread), under the server lock
        self.forwarding = False
        self.forward_at: float | None = None  # monotonic time forwarding starts by itself
        self.remove_tap: Callable[[], None] | None = None
        self.bad_messages = 0
        self.closed = False
        self.overflow = False

    def __repr__(self) -> str:
        return f"socketcand client {self.peer}"


class SocketcandServer:
    """Serve a SimBus over the socketcand protocol on a TCP port (loopback unless allowed)."""

    def __init__(
        self,
        sim: SimBus,
        host: str = "127.0.0.1",
        port: int = 29536,
        channel: str = "can0",
        *,
        allow_remote: bool = False,
        wall_clock: Callable[[], float] = time.time,
    ) -> None:
        if not allow_remote and not is_loopback(host):
            # socketcand has no authentication: anyone who reaches the port drives the motors.
            raise ValueError(
                f"refusing to serve on {host}: not a loopback address (pass allow_remote=True)"
            )
        self.sim = sim
        self.host = host
        self.port = port
        self.channel = channel
        self._wall_clock = wall_clock
        self._lock = threading.Lock()
        self._wake_pending = False
        self._clients: list[_Client] = []
        self._listener: socket.socket | None = None
        self._selector: selectors.BaseSelector | None = None
        self._wake_r, self._wake_w = socket.socketpair()
        self._wake_r.setblocking(False)
        self._wake_w.setblocking(False)
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._failure: Exception | None = None
        self._address = (host, port)

    @property
    def running(self) -> bool:
        return self._thread is not None and self._thread.is_alive()

    @property
    def failure(self) -> Exception | None:
        """The unexpected exception that ended the server thread, if any (it was logged)."""
        return self._failure

    @property
    def address(self) -> tuple[str, int]:
        """The bound host and port (the real port when 0 asked for an ephemeral one)."""
        return self._address

    @property
    def client_count(self) -> int:
        with self._lock:
            return len(self._clients)

    def start(self) -> None:
        if self._thread is not None:
            raise RuntimeError("a SocketcandServer can be started only once")
        family = socket.AF_INET6 if ":" in self.host else socket.AF_INET
        try:
            self._listener = socket.create_server((self.host.strip("[]"), self.port), family=family)
        except OSError:
            self._wake_r.close()
            self._wake_w.close()
            raise
        self._listener.setblocking(False)
        name = self._listener.getsockname()
        self._address = (str(name[0]), int(name[1]))
        self._selector = selectors.DefaultSelector()
        self._selector.register(self._listener, selectors.EVENT_READ)
        self._selector.register(self._wake_r, selectors.EVENT_READ)
        self._thread = threading.Thread(target=self._run, name="socketcand-server", daemon=True)
        self._thread.start()
        log.info("socketcand server listening on %s:%d", *self.address)

    def stop(self) -> None:
        self._stop.set()
        self._wake()
        if self._thread is not None:
            self._thread.join()
        self._wake_r.close()
        self._wake_w.close()

    # ------------------------------------------------------------------------ server thread

    def _run(self) -> None:
        selector = self._selector
        if selector is None:
            raise RuntimeError("start() was not called")
        try:
            while not self._stop.is_set():
                for key, events in selector.select(self._select_timeout()):
                    sock = key.fileobj
                    if sock is self._listener:
                        self._accept()
                    elif sock is self._wake_r:
                        self._drain_wake()
                    elif isinstance(key.data, _Client) and events & selectors.EVENT_READ:
                        self._read(key.data)
                self._service_clients()
        except Exception as exc:
            log.exception("socketcand server stopped by an unexpected error")
            self._failure = exc
        finally:
            for client in list(self._clients):
                self._close(client, "server stopping")
            selector.close()
            if self._listener is not None:
                self._listener.close()

    def _select_timeout(self) -> float | None:
        now = time.monotonic()
        waits = [
            max(0.0, c.forward_at - now)
            for c in self._clients
            if c.forward_at is not None and not c.forwarding
        ]
        return min(waits, default=None)

    def _accept(self) -> None:
        if self._listener is None or self._selector is None:
            return
        try:
            sock, addr = self._listener.accept()
        except BlockingIOError:
            return  # another readiness notification already took the connection
        except OSError as exc:  # e.g. out of file descriptors: refuse this one, keep serving
            log.warning("could not accept a connection: %s", exc)
            return
        sock.setblocking(False)
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        client = _Client(sock, f"{addr[0]}:{addr[1]}")
        client.outbuf += b"< hi >"
        with self._lock:
            self._clients.append(client)
        self._selector.register(sock, selectors.EVENT_READ, client)
        log.info("%r connected", client)

    def _drain_wake(self) -> None:
        # Drain first, then clear the flag: cleared first, a tap waking in between had its byte
        # drained here and left the flag set with an empty pipe, so every later tap skipped its
        # byte and its frames waited for the next socket event (an EMCY after the last client
        # fell silent waited seconds). Frames tapped before the clear go out in this round's
        # _service_clients; later ones send a byte again.
        try:
            while self._wake_r.recv(4096):
                pass
        except BlockingIOError:
            pass  # nothing more to drain
        with self._lock:
            self._wake_pending = False

    def _wake(self) -> None:
        with self._lock:
            if self._wake_pending:
                return
            self._wake_pending = True
        try:
            self._wake_w.send(b"\0")
        except (BlockingIOError, OSError):
            # A full or closed wake pipe means the server thread is awake or gone already.
            return

    def _read(self, client: _Client) -> None:
        try:
            data = client.sock.recv(RECV_SIZE)
        except BlockingIOError:
            return
        except OSError as exc:
            self._close(client, f"receive failed: {exc}")
            return
        if not data:
            self._close(client, "disconnected")
            return
        if QUICKACK is not None:
            # ACK now: a client that left Nagle on holds its next frame until this ACK, and
            # the kernel would delay it up to 40 ms when no reply is due. Linux clears the
            # flag again by itself, so it is set after every read.
            with contextlib.suppress(OSError):
                client.sock.setsockopt(socket.IPPROTO_TCP, QUICKACK, 1)
        client.inbuf += data
        self._handle_input(client)

    def _handle_input(self, client: _Client) -> None:
        buf = client.inbuf
        while not client.closed:
            start = buf.find(b"<")
            if start < 0:
                if buf.strip():
                    self._bad(client, f"text outside < >: {bytes(buf[:40])!r}")
                buf.clear()
                return
            end = buf.find(b">", start)
            if end < 0:
                if len(buf) - start > MAX_MESSAGE:
                    self._close(client, "message too long")
                del buf[:start]
                return
            if buf[:start].strip():
                self._bad(client, f"text outside < >: {bytes(buf[:start][:40])!r}")
            message = bytes(buf[start + 1 : end])
            del buf[: end + 1]
            self._handle_message(client, message.decode("ascii", errors="replace").split())

    def _handle_message(self, client: _Client, tokens: list[str]) -> None:
        if not tokens:
            self._bad(client, "empty message")
            return
        command = tokens[0]
        if client.state is ClientState.RAW and not client.forwarding:
            self._start_forwarding(client)  # it has read our `< ok >` (see RAWMODE_GRACE)
        if command == "open" and client.state is ClientState.AWAIT_OPEN:
            if len(tokens) != 2 or tokens[1] != self.channel:
                # The handshake reply is shown by python-can as "Expected '< ok >' got: …".
                client.outbuf += f"< error could not open bus, serving {self.channel} >".encode()
                log.warning("%r asked for bus %s", client, " ".join(tokens[1:]))
                return
            client.state = ClientState.BCM
            client.outbuf += b"< ok >"
        elif command == "rawmode" and client.state is not ClientState.AWAIT_OPEN:
            client.outbuf += b"< ok >"
            if client.state is not ClientState.RAW:
                self._enter_rawmode(client)
        elif command == "echo":
            client.outbuf += b"< echo >"
        elif command == "send" and client.state is not ClientState.AWAIT_OPEN:
            self._send(client, tokens)
        else:
            # No `< error >` reply in raw mode: python-can would fail to parse it as a frame.
            self._bad(client, f"unsupported in {client.state.value} mode: {' '.join(tokens)}")

    def _send(self, client: _Client, tokens: list[str]) -> None:
        try:
            frame = parse_send(tokens)
        except BadMessageError as exc:
            self._bad(client, str(exc))
            return
        if frame is None:
            log.debug("%r: skipped %s (remote frame or extended id)", client, " ".join(tokens))
            return
        self.sim.inject(frame, origin=client)

    def _enter_rawmode(self, client: _Client) -> None:
        client.state = ClientState.RAW
        client.forward_at = time.monotonic() + RAWMODE_GRACE

        def tap(frame: Frame, _origin: object | None) -> None:
            self._on_tap(client, frame)

        client.remove_tap = self.sim.add_tap(tap, origin=client)

    def _start_forwarding(self, client: _Client) -> None:
        client.forwarding = True
        client.forward_at = None

    def _on_tap(self, client: _Client, frame: Frame) -> None:
        """On the SimBus thread: queue the frame for the client, never block."""
        if frame.rtr:
            return  # socketcand's raw mode cannot express a remote frame
        line = format_frame(frame, self._wall_clock())
        with self._lock:
            if client.closed or client.overflow:
                return
            client.frames += line
            if len(client.frames) > MAX_BUFFERED:
                client.overflow = True
        self._wake()

    def _service_clients(self) -> None:
        now = time.monotonic()
        for client in list(self._clients):
            if client.closed:
                continue
            if not client.forwarding and client.forward_at is not None and now >= client.forward_at:
                self._start_forwarding(client)
            with self._lock:
                overflow = client.overflow
                if client.forwarding and client.frames and not overflow:
                    client.outbuf += client.frames
                    client.frames.clear()
            if overflow or len(client.outbuf) > MAX_BUFFERED:
                self._close(client, "not reading fast enough; dropped")
                continue
            self._flush(client)

    def _flush(self, client: _Client) -> None:
        if client.outbuf:
            try:
                sent = client.sock.send(client.outbuf)
            except BlockingIOError:
                sent = 0
            except OSError as exc:
                self._close(client, f"send failed: {exc}")
                return
            del client.outbuf[:sent]
        if self._selector is not None and not client.closed:
            events = selectors.EVENT_READ | (selectors.EVENT_WRITE if client.outbuf else 0)
            if self._selector.get_key(client.sock).events != events:
                self._selector.modify(client.sock, events, client)

    def _bad(self, client: _Client, reason: str) -> None:
        client.bad_messages += 1
        log.warning("%r: %s", client, reason)
        if client.bad_messages >= MAX_BAD_MESSAGES:
            self._close(client, "too many malformed messages")

    def _close(self, client: _Client, reason: str) -> None:
        if client.closed:
            return
        with self._lock:
            client.closed = True
            if client in self._clients:
                self._clients.remove(client)
        if client.remove_tap is not None:
            client.remove_tap()
        if self._selector is not None:
            self._selector.unregister(client.sock)
        client.sock.close()
        log.info("%r closed: %s", client, reason)
