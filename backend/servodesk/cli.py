"""`servodesk` command line: the web app (`serve`) and field commands for scripts.

    servodesk serve [--sim] [--bind 127.0.0.1] [--port 8000] [--tokens-file F]
                    [--allowed-host NAME] [--forwarded-allow-ips IPS]
                    [--tls-cert PEM --tls-key PEM] [bus flags]
    servodesk scan [--sim] [bus flags]
    servodesk read NODE INDEX SUB [--sim] [bus flags]
    servodesk write NODE INDEX SUB VALUE [--size 1|2|4] [--sim] [bus flags]
    servodesk dump NODE [--sim] [bus flags] > node.dcf
    servodesk eds-check FILE
    servodesk decode-log FILE [--dcf FILE] [--profile N=NAME] [--format text|csv|json|parquet]
                         [-o OUT]

Bus flags are python-can's own (`--interface/--channel/--bitrate/--bus-kwargs`); without them
python-can's config file and environment apply. Every error is one line on stderr and a
non-zero exit code; `--debug` adds the traceback and the libraries' log.
"""

from __future__ import annotations

import argparse
import asyncio
import logging
import os
import sys
import traceback
from collections.abc import AsyncIterator, Awaitable, Callable, Sequence
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any, NoReturn, TypeVar

from can.cli import add_bus_arguments
from tqdm import tqdm

from servodesk import __version__
from servodesk.access.tokens import TokenConfigError, TokenTable
from servodesk.api.security import LOOPBACK_HOSTS
from servodesk.bus.config_check import check_bus_config
from servodesk.errors import ServodeskError
from servodesk.models import BusConfig, BusState
from servodesk.od import OdImportError, lint_report, load_od
from servodesk.services import Services, build_services
from servodesk.settings import Settings
from servodesk.storage.data_dir import data_dir_problem

T = TypeVar("T")
USAGE_ERROR = 2


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


def build_parser() -> argparse.ArgumentParser:
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
    _bus_flags(serve)
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
    _bus_flags(scan)
    scan.add_argument("--timeout-ms", type=int, default=50, help="SDO sweep answer window")

    read = commands.add_parser("read", help="read an object-dictionary entry")
    _bus_flags(read)
    _entry_args(read)

    write = commands.add_parser("write", help="write an object-dictionary entry")
    _bus_flags(write)
    _entry_args(write)
    write.add_argument("value", help='value: 1000, 0x3E8, -5, 1.5, "text"')
    write.add_argument("--size", type=int, choices=(1, 2, 4), help="for entries the OD lacks")

    dump = commands.add_parser("dump", help="save a node's configuration as DCF to stdout")
    _bus_flags(dump)
    dump.add_argument("node", type=_node_id)

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


def _bus_flags(parser: argparse.ArgumentParser) -> None:
    add_bus_arguments(parser)
    parser.add_argument("--sim", action="store_true", help="use the built-in simulated drives")


def _entry_args(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("node", type=_node_id)
    parser.add_argument("index", type=_hex("index", 0xFFFF), help="hexadecimal, e.g. 6041")
    parser.add_argument("sub", type=_hex("sub-index", 0xFF), help="hexadecimal, e.g. 0")


def bus_config(args: argparse.Namespace) -> BusConfig:
    if getattr(args, "sim", False):
        return BusConfig(simulated=True)
    return BusConfig(
        interface=getattr(args, "interface", None),
        channel=getattr(args, "channel", None),
        bitrate=getattr(args, "bitrate", None),
        options=dict(getattr(args, "bus_kwargs", {}) or {}),
    )


def main(argv: Sequence[str] | None = None) -> int:
    raw = list(sys.argv[1:] if argv is None else argv)
    args = build_parser().parse_args(raw)
    _quiet_libraries(args.debug)
    try:
        if args.command == "serve":
            return serve(args, raw)
        if args.command == "eds-check":
            return eds_check(args.file)
        if args.command == "decode-log":
            from servodesk.logs.cli import decode_log

            return decode_log(args)
        return asyncio.run(_field_command(args))
    except ServodeskError as error:
        _say(str(error), debug=args.debug)
        return 1
    except KeyboardInterrupt:
        return 130
    except Exception as error:
        # a failure we did not foresee: one line, the traceback only when asked for
        _say(f"{type(error).__name__}: {error}; run with --debug for the details", args.debug)
        return 1


def _say(message: str, debug: bool) -> None:
    if debug:
        traceback.print_exc()
    print(f"servodesk: {message}", file=sys.stderr)


def _quiet_libraries(debug: bool) -> None:
    """The libraries log what they do to stderr (canopen: "Transfer aborted by client …" before
    our own message about the same timeout); the user gets one message per problem."""
    if debug:
        logging.basicConfig(level=logging.DEBUG, format="%(levelname)s %(name)s: %(message)s")
    else:
        logging.basicConfig(level=logging.CRITICAL + 1, handlers=[logging.NullHandler()])


def serve(args: argparse.Namespace, argv: Sequence[str] = ()) -> int:
    import uvicorn

    from servodesk.app import create_app, server_options

    settings = _serve_settings(args)
    refusal = serve_refusal(settings)
    if refusal is not None:
        print(f"servodesk: {refusal}", file=sys.stderr)
        return USAGE_ERROR
    _use_system_allocator(argv)
    scheme = "https" if settings.tls_cert else "http"
    print(f"ServoDesk {__version__} on {scheme}://{args.bind}:{args.port}", flush=True)
    if not args.debug:
        _say_own_warnings()
    uvicorn.run(
        create_app(settings),
        host=args.bind,
        port=args.port,
        log_level="info",
        ssl_certfile=settings.tls_cert,
        ssl_keyfile=settings.tls_key,
        **server_options(settings),
    )
    return 0


def _say_own_warnings() -> None:
    """The libraries stay quiet (`_quiet_libraries`), but a running server says its own
    warnings on stderr: a stalled event loop, a withheld heartbeat, a stop that could not be
    sent are what a field engineer reads after something went wrong."""
    handler = logging.StreamHandler()
    handler.setFormatter(logging.Formatter("%(levelname)s %(name)s: %(message)s"))
    own = logging.getLogger("servodesk")
    own.addHandler(handler)
    own.setLevel(logging.WARNING)


def _serve_settings(args: argparse.Namespace) -> Settings:
    """The flags over the environment (SERVODESK_TOKENS and the rest stay as set there)."""
    config = bus_config(args)
    given: dict[str, Any] = {
        "bind": args.bind,
        "port": args.port,
        "simulated": config.simulated,
        "interface": config.interface,
        "channel": config.channel,
        "bitrate": config.bitrate,
        "bus_options": dict(config.options),
    }
    if args.tokens_file:
        given["tokens_file"] = Path(args.tokens_file)
    if args.allowed_host:
        given["allowed_hosts"] = ",".join(args.allowed_host)
    if args.forwarded_allow_ips is not None:
        given["forwarded_allow_ips"] = args.forwarded_allow_ips
    if args.tls_cert or args.tls_key:
        given["tls_cert"] = Path(args.tls_cert) if args.tls_cert else None
        given["tls_key"] = Path(args.tls_key) if args.tls_key else None
    return Settings(**given)


def serve_refusal(settings: Settings) -> str | None:
    """Why the server must not start with these settings (one line), or None."""
    secret = settings.tokens.get_secret_value() if settings.tokens else None
    try:
        tokens = TokenTable.load(secret, settings.tokens_file)
    except TokenConfigError as error:
        return f"access tokens: {error}"
    if settings.bind not in LOOPBACK_HOSTS and not tokens.configured:
        return (
            f"refusing to serve on {settings.bind} without access tokens: anyone who can reach "
            'it could move the drives. Set SERVODESK_TOKENS="engineer=…,operator=…,viewer=…" '
            "or --tokens-file FILE (one role=token per line; see docs/security.md)"
        )
    storage = data_dir_problem(settings.data_dir)
    if storage is not None:
        return storage
    if (settings.tls_cert is None) != (settings.tls_key is None):
        return "HTTPS needs both --tls-cert and --tls-key (PEM files)"
    for what, path in (("certificate", settings.tls_cert), ("key", settings.tls_key)):
        if path is not None and not path.is_file():
            return f"the TLS {what} {path} is not a readable file"
    return None


def _use_system_allocator(argv: Sequence[str]) -> None:
    """Run the server on the C library's allocator (PYTHONMALLOC=malloc), re-starting this
    command once with it set. CPython's own allocator keeps memory in 1 MB arenas that go back
    to the system only when entirely empty: after a large dictionary upload is dropped, a few
    objects allocated meanwhile keep most of its arenas, and the server stays tens of MB
    larger for good. glibc returns freed pages (servodesk.od.parser.release_memory), so the
    server's memory follows what it holds (bench/od_upload.py measures both)."""
    if os.environ.get("PYTHONMALLOC") or not sys.platform.startswith("linux"):
        return  # the user chose, or not glibc
    env = {**os.environ, "PYTHONMALLOC": "malloc"}
    sys.stdout.flush()
    os.execve(sys.executable, [sys.executable, "-m", "servodesk.cli", *argv], env)


def eds_check(path: str) -> int:
    """Print every problem in the file; fail only when nothing usable could be read."""
    try:
        model = load_od(path)
    except (OdImportError, OSError) as error:
        print(f"servodesk: {path}: {error}", file=sys.stderr)
        return 1
    report = lint_report(model)
    print(
        f"{path}: {model.format.upper()}, {len(model.objects)} objects, "
        f"{len(model.warnings)} warning(s)"
    )
    if report:
        print(report)
    return 0


@asynccontextmanager
async def _connected(args: argparse.Namespace) -> AsyncIterator[Services]:
    config = check_bus_config(bus_config(args))  # before anything starts
    # each command says which node it wants: no scan of its own after connecting
    services = build_services(Settings(auto_scan=False))
    try:
        status = await services.bus.connect(config)
        if status.state is not BusState.CONNECTED:
            raise ServodeskError(f"could not open the CAN bus: {status.error}")
        yield services
    finally:
        await services.close()


async def _field_command(args: argparse.Namespace) -> int:
    async with _connected(args) as services:
        registry = services.registry
        if args.command == "scan":
            result = await _with_spinner(
                "scanning", registry.scan(sdo_sweep=True, timeout_ms=args.timeout_ms)
            )
            print(f"{'node':>4}  {'state':<16} {'profile':<15} name")
            for node in result.nodes:
                print(
                    f"{node.node:>4}  {node.nmt_state.value:<16} {node.profile:<15} "
                    f"{node.name or ''}"
                )
            print(f"{len(result.nodes)} node(s) in {result.duration_ms} ms", file=sys.stderr)
            return 0
        await registry.add(args.node)
        if args.command == "read":
            value = await services.sdo.read(args.node, args.index, args.sub)
            print(value.text)
            return 0
        if args.command == "write":
            # typed at the terminal by the user it acts as: that is the confirmation
            written = await services.sdo.write(
                args.node, args.index, args.sub, args.value, size=args.size, confirm=True
            )
            print(written.text)
            return 0
        if args.command == "dump":
            text = await _with_progress(
                f"reading node {args.node}",
                lambda progress: services.paramsets.export_dcf(args.node, progress=progress),
            )
            sys.stdout.write(text)
            return 0
    return 2


async def _with_spinner(label: str, work: Awaitable[T]) -> T:
    with tqdm(desc=label, bar_format="{desc}: {elapsed}", file=sys.stderr, leave=False):
        return await work


async def _with_progress(
    label: str, start: Callable[[Callable[[int, int], None]], Awaitable[T]]
) -> T:
    """A progress bar on stderr for work that reports (done, total)."""
    bar: Any = tqdm(desc=label, unit="entry", file=sys.stderr, leave=False)

    def progress(done: int, total: int) -> None:
        bar.total = total
        bar.n = done
        bar.refresh()

    try:
        return await start(progress)
    finally:
        bar.close()


if __name__ == "__main__":
    raise SystemExit(main())
