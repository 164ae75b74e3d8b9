"""The `servodesk` command line's arguments (servodesk/cli.py runs them). Light on purpose: only
what parsing needs is imported here."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import TYPE_CHECKING, NoReturn

from servodesk import __version__

if TYPE_CHECKING:
    from servodesk.models.bus import BusConfig

USAGE_ERROR = 2
BUS_COMMANDS = frozenset({"serve", "scan", "read", "write", "dump", "check-record"})


class OneLineParser(argparse.ArgumentParser):
    """argparse prints the whole usage (several lines with python-can's bus flags) before an
    error; a user needs the error and where to look."""

    def error(self, message: str) -> NoReturn:
        self.exit(USAGE_ERROR, f"{self.prog}: {message} (see {self.prog} --help)\n")


def _hex(what: str, maximum: int) -> Callable[[str], int]:
    def parse(text: str) -> int:
        try:
            value = int(text, 16)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{what} {text!r} is not hexadecimal (e.g. {'6041' if maximum > 0xFF else '0'})"
            ) from None
        if not 0 <= value <= maximum:
            raise argparse.ArgumentTypeError(f"{what} {text!r} is outside 0–{maximum:X}")
        return value

    parse.__name__ = what  # argparse names the type in some messages
    return parse


def _node_id(text: str) -> int:
    try:
        value = int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"node id {text!r} is not a number") from None
    if not 1 <= value <= 127:
        raise argparse.ArgumentTypeError(f"node id {value} is outside 1–127")
    return value


def build_parser(*, bus_flags: bool = True) -> argparse.ArgumentParser:
    """The whole command line; `bus_flags` False leaves python-can's bus flags out (importing
    python-can brings asammdf and pandas: a second, which `servodesk --help` and `eds-check`
    must not wait for; `main` adds them for the commands that open a bus)."""
    parser = OneLineParser(
        prog="servodesk",
        description="Commissioning and diagnostics for CANopen (CiA 301 / CiA 402) servo drives.",
    )
    parser.add_argument("--version", action="version", version=f"servodesk {__version__}")
    parser.add_argument(
        "--debug", action="store_true", help="show tracebacks and the libraries' log"
    )
    commands = parser.add_subparsers(
        dest="command", required=True, metavar="COMMAND", parser_class=OneLineParser
    )

    serve = commands.add_parser("serve", help="run the web app (http://127.0.0.1:8000)")
    _bus_flags(serve, bus_flags)
    serve.add_argument(
        "--bind", default="127.0.0.1", help="address to listen on (beyond loopback: tokens)"
    )
    serve.add_argument("--port", type=int, default=8000)
    serve.add_argument(
        "--tokens-file", help="access tokens, one role=token (or user:role=token) per line"
    )
    serve.add_argument(
        "--allowed-host", action="append", default=[],
        help="a host name users reach the server by (repeatable; checked against Host/Origin)",
    )  # fmt: skip
    serve.add_argument(
        "--forwarded-allow-ips",
        help="reverse proxies whose X-Forwarded-For is believed (comma-separated; default none)",
    )
    serve.add_argument("--tls-cert", help="serve HTTPS: the certificate (PEM)")
    serve.add_argument("--tls-key", help="serve HTTPS: the private key (PEM)")

    scan = commands.add_parser("scan", help="find the nodes on the bus")
    _bus_flags(scan, bus_flags)
    scan.add_argument("--timeout-ms", type=int, default=50, help="SDO sweep answer window")

    read = commands.add_parser("read", help="read an object-dictionary entry")
    _bus_flags(read, bus_flags)
    _entry_args(read)

    write = commands.add_parser("write", help="write an object-dictionary entry")
    _bus_flags(write, bus_flags)
    _entry_args(write)
    write.add_argument("value", help='value: 1000, 0x3E8, -5, 1.5, "text"')
    write.add_argument("--size", type=int, choices=(1, 2, 4), help="for entries the OD lacks")

    dump = commands.add_parser("dump", help="save a node's configuration as DCF to stdout")
    _bus_flags(dump, bus_flags)
    dump.add_argument("node", type=_node_id)

    record = commands.add_parser(
        "check-record",
        help="compare a drive with its commissioning bundle (exit 0 same, 1 differs, 2 error)",
        description="Compare the drive as it is now with the hand-over in a commissioning "
        "bundle (GET /api/commissioning/{id}/report?format=zip): every parameter and PDO "
        "entry that differs, with who changed it where the bundle's audit.csv knows, the "
        "drive's error history (1003h) and its firmware. Needs no server: the bundle and the "
        "bus are enough. Exit status: 0 nothing differs, 1 something differs, 2 an error "
        "(unreadable bundle, bus or node not reachable).",
    )
    _bus_flags(record, bus_flags)
    record.add_argument("bundle", help="the bundle zip (servodesk-commissioning-…zip)")
    record.add_argument(
        "--node", type=_node_id, help="the node to check (default: the record's node)"
    )
    record.add_argument("--json", action="store_true", help="print the result as JSON")

    check = commands.add_parser("eds-check", help="load an EDS/DCF/XDD and list its problems")
    check.add_argument("file")

    decode = commands.add_parser(
        "decode-log", help="decode a CAN log (candump, ASC, BLF, TRC, CSV) into a timeline"
    )
    decode.add_argument("file", help="the log: .log .asc .blf .trc .csv (.mf4 with asammdf)")
    decode.add_argument("--dcf", help="a DCF of one node: its PDO mappings, identity, bitrate")
    decode.add_argument(
        "--format", choices=("text", "csv", "json", "parquet"), default="text",
        help="how the events are written (json: JSON lines; parquet needs -o)",
    )  # fmt: skip
    decode.add_argument("-o", "--output", help="write the events here instead of stdout")
    decode.add_argument(
        "--bitrate", type=int, help="bit/s for the bus load (default: DCF or 500000)"
    )
    decode.add_argument(
        "--profile", action="append", metavar="NODE=PROFILE",
        help="which drive a node is, e.g. 1=mdi-s1c (its alarms and objects); repeatable",
    )  # fmt: skip
    return parser


def _bus_flags(parser: argparse.ArgumentParser, with_python_can: bool) -> None:
    if with_python_can:
        from can.cli import add_bus_arguments

        add_bus_arguments(parser)
    parser.add_argument("--sim", action="store_true", help="use the built-in simulated drives")


def _entry_args(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("node", type=_node_id)
    parser.add_argument("index", type=_hex("index", 0xFFFF), help="hexadecimal, e.g. 6041")
    parser.add_argument("sub", type=_hex("sub-index", 0xFF), help="hexadecimal, e.g. 0")


def bus_config(args: argparse.Namespace) -> BusConfig:
    from servodesk.models.bus import BusConfig

    if getattr(args, "sim", False):
        return BusConfig(simulated=True)
    return BusConfig(
        interface=getattr(args, "interface", None),
        channel=getattr(args, "channel", None),
        bitrate=getattr(args, "bitrate", None),
        options=dict(getattr(args, "bus_kwargs", {}) or {}),
    )
