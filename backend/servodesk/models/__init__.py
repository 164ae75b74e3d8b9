"""Every pydantic model the API sends or receives, one module per topic: the one place a model
lives (docs/architecture.md, "Packages").

The convention: an API model (a request body, a response, a WebSocket message, the error body)
is defined here and nowhere else; feature packages (servodesk.pdo, servodesk.motion, …) hold
behaviour and import the models they build from here. The package is on the floor of the
layers (pyproject.toml, [tool.importlinter]): its modules import only each other, `base` (what
every model builds on), servodesk_protocol, pydantic and the standard library.

This module re-exports nothing: import a model from its topic module
(`from servodesk.models.bus import BusStatus`).
"""
