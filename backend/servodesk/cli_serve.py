"""`servodesk serve`: the settings from the flags, the checks before the server starts, and the
server (imported only for this command: uvicorn and the app are most of a second)."""

from __future__ import annotations

import argparse
import logging
import os
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from servodesk import __version__
from servodesk.access.tokens import TokenConfigError, TokenTable
from servodesk.api.security import LOOPBACK_HOSTS
from servodesk.cli_args import USAGE_ERROR, bus_config
from servodesk.settings import Settings
from servodesk.storage.data_dir import data_dir_problem


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
