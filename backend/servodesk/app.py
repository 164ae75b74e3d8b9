"""The web app: `create_app(settings)` builds the services and owns them for its lifetime."""

from __future__ import annotations

import importlib
import logging
import socket
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from pathlib import Path
from typing import Any

from fastapi import FastAPI
from starlette.types import Message

from servodesk import __version__
from servodesk.access.guard import Access, AccessGuard
from servodesk.access.sessions import LoginLimiter
from servodesk.access.tokens import TokenTable
from servodesk.api import rerun_proxy, ws
from servodesk.api.audited import outcome_of
from servodesk.api.errors import install_error_handlers
from servodesk.api.route_table import add_api_routes
from servodesk.api.schema import install_schema
from servodesk.api.security import FramingGuard, HostGuard, SameOriginGuard, ServedHosts
from servodesk.api.static import mount_frontend
from servodesk.bus.connection import BusFactory
from servodesk.errors import ServodeskError
from servodesk.heap import quiet_start, settle_after_start
from servodesk.models.bus import BusConfig
from servodesk.services import Services, build_services
from servodesk.settings import Settings

log = logging.getLogger(__name__)

STATIC_DIR = Path(__file__).parent / "static"

# Modules the server would otherwise import on the loop at their first use, each import a stall
# (100+ ms measured under load: anyio's asyncio backend at the first page, its streams at the
# first file or WebSocket): imported with this module, before any loop runs.
LAZY_IMPORTS = (
    "anyio._backends._asyncio",
    "anyio._core._sockets",
    "anyio._core._streams",
    "anyio.streams.memory",
    "anyio.streams.stapled",
    "anyio.streams.tls",
)
for _name in LAZY_IMPORTS:
    importlib.import_module(_name)


def create_app(
    settings: Settings | None = None,
    *,
    bus_factory: BusFactory | None = None,
    static_dir: Path | None = STATIC_DIR,
) -> FastAPI:
    settings = settings or Settings()

    @asynccontextmanager
    async def lifespan(app: FastAPI) -> AsyncIterator[None]:
        quiet_start()
        try:
            services = build_services(settings, bus_factory=bus_factory, describe_error=outcome_of)
            app.state.services = services
            await services.open()
            services.start()
            await _connect_at_start(services)
            await _prepare_routes(app)
        finally:
            settle_after_start()  # start-up's objects out of every later full collection
        try:
            yield
        finally:
            await services.close()

    app = FastAPI(
        title="ServoDesk",
        version=__version__,
        description="Commissioning and diagnostics for CANopen (CiA 301 / CiA 402) servo drives.",
        lifespan=lifespan,
        openapi_url="/api/openapi.json",
        docs_url="/api/docs",
        redoc_url=None,
        # no OpenTelemetry here: FastAPI would otherwise ask the providers on every request
        telemetry={"tracing": False, "metrics": False, "logs": False},
    )
    # Middleware runs last-added first: Host, then Origin, then who is asking (api/security.py,
    # access/guard.py). A bad token in the settings stops here with TokenConfigError.
    hosts = served_hosts(settings)
    app.state.access = Access(
        TokenTable.load(
            settings.tokens.get_secret_value() if settings.tokens else None, settings.tokens_file
        ),
        secure_cookies=settings.tls_cert is not None,
        limiter=LoginLimiter(
            per_client=settings.token_failures_per_client,
            overall=settings.token_failures_overall,
        ),
    )
    app.state.hosts = hosts
    app.add_middleware(AccessGuard, access=app.state.access)
    # State-changing requests from other sites' pages are refused.
    app.add_middleware(SameOriginGuard, hosts=hosts)
    # Requests naming another host are refused (DNS rebinding); added last, so checked first.
    app.add_middleware(HostGuard, hosts=hosts)
    # Outermost: every answer, refusals included, says who may frame it (clickjacking).
    app.add_middleware(FramingGuard)
    install_error_handlers(app)
    install_schema(app)
    ws.install_live_schema(app)
    add_api_routes(app, settings)
    # the rerun viewer (/rerun/) and its gRPC-web at the root, before the frontend's catch-all
    app.include_router(rerun_proxy.root_router)
    if static_dir is not None:
        mount_frontend(app, static_dir)
    return app


WILDCARD_BINDS = frozenset({"0.0.0.0", "::", ""})


def served_hosts(settings: Settings) -> ServedHosts:
    """Loopback, the address the server is bound to (unless it is a wildcard: then the
    machine's own name) and the names in `allowed_hosts`."""
    extra = [h for h in settings.allowed_hosts.split(",") if h.strip()]
    if settings.bind in WILDCARD_BINDS:
        extra += [socket.gethostname(), socket.getfqdn()]
    else:
        extra.append(settings.bind)
    return ServedHosts(extra)


def server_options(settings: Settings) -> dict[str, Any]:
    """uvicorn's options that the app's security rests on: forwarded headers are believed only
    from the proxies the settings name (uvicorn would otherwise believe any loopback client)."""
    proxies = settings.forwarded_allow_ips.strip()
    return {"proxy_headers": bool(proxies), "forwarded_allow_ips": proxies or None}


async def _prepare_routes(app: FastAPI) -> None:
    """FastAPI prepares an included router's routes (validators, response models) the first
    time a request is matched against them: hundreds of milliseconds on the loop for the first
    requests after start-up, a quick stop among them (the API's own routes are built with the
    app, `add_api_routes`; the rerun viewer's router is included). A WebSocket request for a
    path nobody serves walks them all (the frontend's catch-all takes only HTTP), once, here
    (past the middleware: no token needed); the router answers it by closing."""
    scope = {
        "type": "websocket",
        "path": "/api/-",
        "raw_path": b"/api/-",
        "root_path": "",
        "query_string": b"",
        "headers": [],
        "server": ("127.0.0.1", 0),
        "client": ("127.0.0.1", 0),
        "subprotocols": [],
        "app": app,
    }

    async def receive() -> Message:
        return {"type": "websocket.connect"}

    async def send(_: Message) -> None:
        pass

    await app.router(scope, receive, send)


async def _connect_at_start(services: Services) -> None:
    """Connect the bus the settings name (or the simulated drives) and scan it once."""
    settings = services.settings
    if settings.simulated:
        config = BusConfig(simulated=True)
    elif settings.interface or settings.channel:
        config = BusConfig(
            interface=settings.interface,
            channel=settings.channel,
            bitrate=settings.bitrate,
            options=dict(settings.bus_options),
        )
    else:
        return  # the user connects from the Network page
    try:
        await services.bus.connect(config)
    except ServodeskError as error:
        # The server still starts: the Network page shows the error and offers to reconnect.
        log.warning("could not connect at start-up: %s", error)
        return
    await services.registry.settled()  # the scan that follows every connect
