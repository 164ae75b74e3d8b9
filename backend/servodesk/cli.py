"""`servodesk` command line: the web app (`serve`) and field commands for scripts.

    servodesk serve [--sim] [--bind 127.0.0.1] [--port 8000] [--tokens-file F]
                    [--allowed-host NAME] [--forwarded-allow-ips IPS]
                    [--tls-cert PEM --tls-key PEM] [bus flags]
    servodesk scan [--sim] [bus flags]
    servodesk read NODE INDEX SUB [--sim] [bus flags]
    servodesk write NODE INDEX SUB VALUE [--size 1|2|4] [--sim] [bus flags]
    servodesk dump NODE [--sim] [bus flags] > node.dcf
    servodesk eds-check FILE
    servodesk check-record BUNDLE.zip [--node N] [--json] [--sim] [bus flags]
    servodesk decode-log FILE [--dcf FILE] [--profile N=NAME] [--format text|csv|json|parquet]
                         [-o OUT]

Bus flags are python-can's own (`--interface/--channel/--bitrate/--bus-kwargs`); without them
python-can's config file and environment apply. Every error is one line on stderr and a
non-zero exit code; `--debug` adds the traceback and the libraries' log.
"""

from __future__ import annotations

import asyncio
import logging
import sys
import traceback
from collections.abc import Sequence

from servodesk.cli_args import BUS_COMMANDS, USAGE_ERROR, build_parser, bus_config
from servodesk.errors import ServodeskError

__all__ = ["USAGE_ERROR", "build_parser", "bus_config", "eds_check", "main"]


def main(argv: Sequence[str] | None = None) -> int:
    raw = list(sys.argv[1:] if argv is None else argv)
    command = next((word for word in raw if not word.startswith("-")), None)
    args = build_parser(bus_flags=command in BUS_COMMANDS).parse_args(raw)
    _quiet_libraries(args.debug)
    try:
        if args.command == "serve":
            from servodesk.cli_serve import serve

            return serve(args, raw)
        if args.command == "eds-check":
            return eds_check(args.file)
        if args.command == "decode-log":
            from servodesk.logs.cli import decode_log

            return decode_log(args)
        if args.command == "check-record":
            from servodesk.cli_check import check_record

            return asyncio.run(check_record(args))
        from servodesk.cli_field import field_command

        return asyncio.run(field_command(args))
    except ServodeskError as error:
        _say(str(error), debug=args.debug)
        return _failed(args.command)
    except KeyboardInterrupt:
        return 130
    except Exception as error:
        # a failure we did not foresee: one line, the traceback only when asked for
        _say(f"{type(error).__name__}: {error}; run with --debug for the details", args.debug)
        return _failed(args.command)


def _failed(command: str) -> int:
    # check-record's 1 means "the drive differs": an error must not look like an answer
    return USAGE_ERROR if command == "check-record" else 1


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


def eds_check(path: str) -> int:
    """Print every problem in the file; fail only when nothing usable could be read."""
    from servodesk.od import OdImportError, lint_report, load_od

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


if __name__ == "__main__":
    raise SystemExit(main())
