"""The OpenAPI schema as clients see it: every error an operation can answer has the one
documented shape (ErrorBody), FastAPI's own validation-error models are replaced by it, and the
statuses every operation shares are declared once here instead of on each route."""

from __future__ import annotations

from typing import Any

from fastapi import FastAPI
from fastapi.openapi.utils import get_openapi
from starlette.routing import compile_path

from servodesk.access.policy import required_role

ERROR_REF = {"$ref": "#/components/schemas/ErrorBody"}
CHANGES_STATE = frozenset({"post", "put", "patch", "delete"})
FASTAPI_ONLY = ("HTTPValidationError", "ValidationError")


def _error(description: str) -> dict[str, Any]:
    return {"description": description, "content": {"application/json": {"schema": ERROR_REF}}}


def _own_error_model(response: dict[str, Any]) -> bool:
    """A route declared an ErrorBody subclass (MotionErrorBody): keep it."""
    ref = response.get("content", {}).get("application/json", {}).get("schema", {}).get("$ref")
    return isinstance(ref, str) and ref.rsplit("/", 1)[-1] not in (*FASTAPI_ONLY, "ErrorBody")


def build_schema(app: FastAPI) -> dict[str, Any]:
    if app.openapi_schema is not None:
        return app.openapi_schema
    schema = get_openapi(
        title=app.title,
        version=app.version,
        description=app.description,
        routes=app.routes,
    )
    for path, item in schema.get("paths", {}).items():
        for method, operation in item.items():
            if not isinstance(operation, dict) or "responses" not in operation:
                continue
            responses: dict[str, Any] = operation["responses"]
            for status, response in responses.items():
                if not status.startswith("2") and not _own_error_model(response):
                    # errors are JSON even where the success is text (GET …/dcf)
                    responses[status] = _error(response.get("description", "Error"))
            if operation.get("parameters") or operation.get("requestBody"):
                responses["422"] = _error("Invalid request: what is wrong, per field")
            if operation.get("requestBody"):
                responses.setdefault("400", _error("The body could not be parsed"))
            if required_role(method, path) is not None:
                responses.setdefault(
                    "401", _error("A login is needed: access tokens are configured")
                )
            if method in CHANGES_STATE:
                responses.setdefault(
                    "403", _error("Refused: the caller's role may not, or another site's page")
                )
    schemas = schema.get("components", {}).get("schemas", {})
    for name in FASTAPI_ONLY:
        schemas.pop(name, None)
    app.openapi_schema = schema
    return schema


def install_schema(app: FastAPI) -> None:
    def openapi() -> dict[str, Any]:
        return build_schema(app)

    app.openapi = openapi  # type: ignore[method-assign]  # FastAPI's documented override


def allowed_methods(app: FastAPI, path: str) -> list[str]:
    """Every method the schema offers at `path`, for a 405's `Allow` (Starlette's own names
    only the first route it tried: GET where PUT is allowed too)."""
    matching: list[tuple[int, set[str]]] = []
    for template, item in build_schema(app).get("paths", {}).items():
        regex, _, params = compile_path(template)
        if regex.match(path):
            matching.append((len(params), {method.upper() for method in item}))
    # the most literal templates name the resource: /api/logs/decode is not a {log_id}
    fewest = min((count for count, _ in matching), default=0)
    methods: set[str] = set()
    for count, offered in matching:
        if count == fewest:
            methods |= offered
    if "GET" in methods:
        methods.add("HEAD")
    return sorted(methods)
