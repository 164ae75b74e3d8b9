"""`servodesk-sim`: simulated drives on a python-can bus, optionally served over socketcand.

    servodesk-sim [-i INTERFACE -c CHANNEL -b BITRATE --bus-kwargs …] --node 4:mdi-s1c
                  [--node 5:kinco …] [--serve 127.0.0.1:29536]

Runs until SIGINT or SIGTERM, then disconnects clients, stops the drives and closes the bus.
"""

from __future__ import annotations

import argparse
import logging
import signal
import sys
import threading
from collections.abc import Callable, Collection, Iterator, Sequence
from contextlib import ExitStack, contextmanager
from types import FrameType

import can
from can.cli import add_bus_arguments, create_bus_from_namespace

from servodesk_sim.runner import SimBus, SimBusStats, SimNode
from servodesk_sim.socketcand_server import SocketcandServer, is_loopback

log = logging.getLogger(__name__)

NodeFactory = Callable[[int, str], SimNode]

DEFAULT_INTERFACE = "virtual"
DEFAULT_CHANNEL = "servodesk"
DEFAULT_SERVE = "127.0.0.1:29536"
SERVED_CHANNEL = "can0"
WATCH_PERIOD = 0.5  # s between checks that the worker threads are still alive


def parse_node(text: str) -> tuple[int, str]:
    """`ID:PROFILE` → (node id, profile); the id is decimal or 0x-hex, 1–127."""
    id_text, sep, profile = text.partition(":")
    if not sep or not id_text or not profile:
        raise argparse.ArgumentTypeError(f"{text!r} is not ID:PROFILE (for example 4:mdi-s1c)")
    try:
        node_id = int(id_text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"node id {id_text!r} is not a number") from None
    if not 1 <= node_id <= 127:
        raise argparse.ArgumentTypeError(f"node id {node_id} is outside 1–127")
    return node_id, profile


def parse_serve(text: str) -> tuple[str, int]:
    """`HOST:PORT` → (host, port); only IPv4 loopback hosts (and `localhost`) are accepted."""
    host, sep, port_text = text.rpartition(":")
    host = host.strip("[]")
    if not sep or not host:
        raise argparse.ArgumentTypeError(f"{text!r} is not HOST:PORT (for example {DEFAULT_SERVE})")
    try:
        port = int(port_text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"port {port_text!r} is not a number") from None
    if not 0 <= port <= 65535:
        raise argparse.ArgumentTypeError(f"port {port} is outside 0–65535")
    if ":" in host:
        raise argparse.ArgumentTypeError(
            f"cannot serve on {host}: python-can's socketcand client connects over IPv4 only"
        )
    if not is_loopback(host):
        # socketcand has no authentication: whoever reaches the port can move the axes.
        raise argparse.ArgumentTypeError(
            f"refusing to serve on {host}: only loopback addresses (127.0.0.1, localhost)"
        )
    return host, port


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="servodesk-sim",
        description="Simulated CANopen servo drives on a python-can bus. Without bus arguments "
        f"the drives sit on python-can's in-process bus (-i {DEFAULT_INTERFACE} "
        f"-c {DEFAULT_CHANNEL}); use --serve to let other processes join it.",
    )
    add_bus_arguments(parser)
    parser.add_argument(
        "--node",
        dest="nodes",
        action="append",
        type=parse_node,
        required=True,
        metavar="ID:PROFILE",
        help="a simulated drive: node id 1-127 and profile, for example 4:mdi-s1c "
        "(repeat for more drives)",
    )
    parser.add_argument(
        "--serve",
        nargs="?",
        const=DEFAULT_SERVE,
        type=parse_serve,
        metavar="HOST:PORT",
        help="serve the bus to other processes over the socketcand protocol on a loopback "
        f"address (default {DEFAULT_SERVE}; port 0 picks a free port)",
    )
    parser.add_argument(
        "-v",
        "--verbose",
        action="count",
        default=0,
        help="log more (-v: info, -vv: debug)",
    )
    return parser


def check_nodes(
    parser: argparse.ArgumentParser,
    nodes: Sequence[tuple[int, str]],
    profiles: Collection[str],
) -> None:
    """Exit with a usage error for duplicate node ids or unknown profiles."""
    seen: set[int] = set()
    for node_id, profile in nodes:
        if node_id in seen:
            parser.error(f"node id {node_id} is given twice")
        seen.add(node_id)
        if profile not in profiles:
            known = ", ".join(sorted(profiles))
            parser.error(f"unknown profile {profile!r} for node {node_id} (known: {known})")


def connect_hint(host: str, port: int) -> str:
    """How another process joins the served bus (python-can's own tools and API)."""
    return (
        f"listening on {host}:{port} (socketcand, channel {SERVED_CHANNEL})\n"
        f"  watch:  python -m can.logger -i socketcand -c {SERVED_CHANNEL} "
        f"--bus-kwargs host={host} port={port}\n"
        f'  Python: can.Bus(interface="socketcand", host="{host}", port={port}, '
        f'channel="{SERVED_CHANNEL}")'
    )


@contextmanager
def _stop_on_signals(stop: threading.Event) -> Iterator[None]:
    """SIGINT/SIGTERM set `stop`; the previous handlers come back afterwards."""
    if threading.current_thread() is not threading.main_thread():
        yield  # signal handlers can only be installed from the main thread
        return

    def handler(signum: int, _frame: FrameType | None) -> None:
        log.info("received %s, stopping", signal.Signals(signum).name)
        stop.set()

    previous = {sig: signal.signal(sig, handler) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)


def _open_bus(args: argparse.Namespace) -> tuple[can.BusABC, str]:
    """The bus from python-can's flags (virtual `servodesk` without any) and a note on it."""
    note = ""
    if "interface" not in args and "channel" not in args:
        args.interface, args.channel = DEFAULT_INTERFACE, DEFAULT_CHANNEL
        note = " (default; only this process and --serve clients can reach it)"
    elif getattr(args, "interface", None) == DEFAULT_INTERFACE and "channel" not in args:
        args.channel = DEFAULT_CHANNEL
    return create_bus_from_namespace(args), note


def summary(stats: SimBusStats) -> str:
    return (
        f"stopped: {stats.ticks} ticks, {stats.overruns} overruns, "
        f"max tick lateness {stats.max_lateness * 1e3:.1f} ms, {stats.frames_out} frames sent, "
        f"{stats.frames_in} received, {stats.send_errors + stats.recv_errors} bus errors"
    )


def _default_factory(bitrate: int | None) -> NodeFactory:
    from servodesk_sim.drive import create_drive  # the drives pull in the whole simulator

    def make(node_id: int, profile: str) -> SimNode:
        return create_drive(node_id, profile, bus_bitrate=bitrate)

    return make


def _default_profiles() -> Collection[str]:
    from servodesk_data import PROFILE_NAMES

    return tuple(PROFILE_NAMES)


def main(
    argv: Sequence[str] | None = None,
    *,
    make_node: NodeFactory | None = None,
    profile_names: Collection[str] | None = None,
) -> int:
    """Run the simulator until SIGINT/SIGTERM; returns the exit status.

    `make_node` and `profile_names` replace the real drives (tests run it with stand-in nodes).
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    logging.basicConfig(
        level=max(logging.DEBUG, logging.WARNING - 10 * args.verbose),
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
    )
    if getattr(args, "interface", None) == "udp_multicast":
        # It multicasts every frame to the local network (the project never uses it).
        parser.error(
            "udp_multicast sends the drives' frames to the local network; "
            "use --serve to share the bus with other processes on this machine"
        )
    nodes: list[tuple[int, str]] = args.nodes
    check_nodes(parser, nodes, _default_profiles() if profile_names is None else profile_names)
    factory = make_node or _default_factory(getattr(args, "bitrate", None))
    try:
        sim_nodes = [factory(node_id, profile) for node_id, profile in nodes]
    except ValueError as exc:
        parser.error(str(exc))

    stop = threading.Event()
    with ExitStack() as stack:
        # Installed first, so Ctrl+C during start-up also shuts down cleanly.
        stack.enter_context(_stop_on_signals(stop))
        try:
            bus, note = _open_bus(args)
        except argparse.ArgumentError as exc:
            print(f"servodesk-sim: error: cannot open the bus: {exc.__cause__}", file=sys.stderr)
            return 1
        stack.callback(bus.shutdown)
        print(f"bus: {bus.channel_info}{note}")
        sim = SimBus(bus, sim_nodes)
        sim.start()
        stack.callback(lambda: print(summary(sim.stats)))
        stack.callback(sim.stop)
        for node_id, profile in nodes:
            print(f"node {node_id}: {profile}")

        server: SocketcandServer | None = None
        if args.serve is not None:
            host, port = args.serve
            server = SocketcandServer(sim, host, port, SERVED_CHANNEL)
            try:
                server.start()
            except OSError as exc:
                print(
                    f"servodesk-sim: error: cannot serve on {host}:{port}: {exc}", file=sys.stderr
                )
                return 1
            stack.callback(server.stop)
            print(connect_hint(*server.address))
        print("running; press Ctrl+C to stop", flush=True)
        while not stop.wait(WATCH_PERIOD):
            if not sim.running:
                print("servodesk-sim: error: the simulated bus stopped", file=sys.stderr)
                return 1
            if server is not None and not server.running:
                print("servodesk-sim: error: the socketcand server stopped", file=sys.stderr)
                return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
