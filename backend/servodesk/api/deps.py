"""Typed dependencies: routers ask for the app's services, nothing global."""

from __future__ import annotations

from typing import Annotated

from fastapi import Depends, Path, Request

from servodesk.errors import InvalidValueError
from servodesk.services import Services


async def get_services(request: Request) -> Services:
    # async on purpose: FastAPI runs a plain `def` dependency in a worker thread, one thread
    # hop per request for a dictionary lookup.
    services: Services = request.app.state.services
    return services


ServicesDep = Annotated[Services, Depends(get_services)]
NodeId = Annotated[int, Path(ge=1, le=127, description="CANopen node id 1–127")]
# Object-dictionary paths are hexadecimal without prefix, exactly as the manuals print them.
Index = Annotated[str, Path(pattern=r"^[0-9A-Fa-f]{4}$", description="index, 4 hex digits: 6041")]
Subindex = Annotated[
    str, Path(pattern=r"^[0-9A-Fa-f]{1,2}$", description="sub-index, 1–2 hex digits: 0, 0A")
]


def parse_hex(text: str, *, maximum: int, what: str) -> int:
    """Index/sub-index path segments are hexadecimal without prefix: `6041`, `0A`."""
    try:
        value = int(text, 16)
    except ValueError:
        raise InvalidValueError(f"{what} {text!r} is not hexadecimal (e.g. 6041, 0A)") from None
    if not 0 <= value <= maximum:
        raise InvalidValueError(f"{what} {text!r} is out of range (0–{maximum:X}h)")
    return value
