"""The API's routes, flat on the app's own router, each with its body limit.

Building a route is the expensive part of `create_app` (FastAPI analyses the endpoint's
signature and builds a pydantic validator for every parameter and response model: ~0.25 s for
the API's 100-odd routes). The analysed routes depend on nothing of an app but the body limits,
so one process builds them once per set of limits (`_templates`) and each app gets its own
copies, whose request handlers are rebuilt for that app: a handler keeps the app it asks for
dependency overrides, and `SaysLimit` keeps the limit it names."""

from __future__ import annotations

import copy
from dataclasses import dataclass
from functools import cache

from fastapi import APIRouter, FastAPI

# FastAPI's own wrapper for a route's max_body_size, as APIRoute applies it (pinned 0.165.x)
from fastapi._body_limit import wrap_app_with_body_limit
from fastapi.routing import APIRoute, APIWebSocketRoute, request_response

from servodesk.api import (
    access,
    audit,
    bus,
    commissioning,
    drive,
    faults,
    health,
    jog,
    logs,
    nodes,
    od,
    params,
    paramsets,
    pdos,
    recording,
    rerun_proxy,
    scope,
    sdo,
    ws,
)
from servodesk.api import events as events_api
from servodesk.api.body_limits import BodyLimit, SaysLimit, log_upload_limit, route_body_limit
from servodesk.settings import Settings


def api_routers() -> list[APIRouter]:
    """The API's routers, in the order their routes are matched (and listed in the schema).
    SDO first: live views poll its reads (each route tried before costs a match), and no
    other route matches its paths, so the order changes no answer."""
    modules = (sdo, health, access, bus, nodes, od, params, paramsets, pdos, drive, jog)
    routers = [module.router for module in modules]
    routers += [bus.sync_router, pdos.bus_router, ws.router]
    routers.append(rerun_proxy.router)  # /api/scope/viewer
    routers += [m.router for m in (faults, events_api, logs, recording, scope, audit)]
    routers.append(commissioning.router)
    return routers


@dataclass(frozen=True)
class _Template:
    route: APIRoute | APIWebSocketRoute
    limit: BodyLimit | None  # None for a WebSocket route


def add_api_routes(app: FastAPI, settings: Settings, prefix: str = "/api") -> None:
    """Every API route on the app's own router, under `prefix`.

    Copied, not included: FastAPI keeps an included router as one route that matches its
    routes again on each request, level by level, and /api → resource is two levels: 0.1–0.2
    ms of every request went to finding its route. Flat, a request is matched once; the
    routes and the schema are the same (frontend/openapi.json). Each route takes a body up to
    its limit (api/body_limits.py), refused with 413 before it is parsed."""
    for template in _templates(log_upload_limit(settings), prefix):
        if isinstance(template.route, APIWebSocketRoute):
            ws_route = template.route
            app.router.add_api_websocket_route(
                prefix + ws_route.path,
                ws_route.endpoint,
                ws_route.name,
                dependencies=ws_route.dependencies,
            )
            continue
        assert template.limit is not None
        route = copy.copy(template.route)
        route.dependency_overrides_provider = app
        handler = request_response(route.get_route_handler())
        route.app = SaysLimit(
            wrap_app_with_body_limit(handler, route.max_body_size), template.limit
        )
        app.router.routes.append(route)


@cache
def _templates(log_limit: BodyLimit, prefix: str) -> tuple[_Template, ...]:
    """The analysed routes for one log upload limit (the only limit a setting changes)."""
    scratch = APIRouter()
    templates: list[_Template] = []
    for router in api_routers():
        for route in router.routes:
            if isinstance(route, APIWebSocketRoute):
                templates.append(_Template(route, None))  # built per app: few and cheap
                continue
            if not isinstance(route, APIRoute):
                raise TypeError(f"{route!r}: an API router holds API routes only")
            limit = route_body_limit(route, log_limit)
            scratch.add_api_route(
                prefix + route.path,
                route.endpoint,
                response_model=route.response_model,
                status_code=route.status_code,
                tags=route.tags,
                dependencies=route.dependencies,
                summary=route.summary,
                description=route.description,
                response_description=route.response_description,
                responses=route.responses,
                deprecated=route.deprecated,
                methods=route.methods,
                operation_id=route.operation_id,
                response_model_include=route.response_model_include,
                response_model_exclude=route.response_model_exclude,
                response_model_by_alias=route.response_model_by_alias,
                response_model_exclude_unset=route.response_model_exclude_unset,
                response_model_exclude_defaults=route.response_model_exclude_defaults,
                response_model_exclude_none=route.response_model_exclude_none,
                include_in_schema=route.include_in_schema,
                response_class=route.response_class,
                name=route.name,
                route_class_override=type(route),
                callbacks=route.callbacks,
                openapi_extra=route.openapi_extra,
                generate_unique_id_function=route.generate_unique_id_function,
                max_body_size=limit.size,
            )
            added = scratch.routes[-1]
            assert isinstance(added, APIRoute)
            templates.append(_Template(added, limit))
    return tuple(templates)
